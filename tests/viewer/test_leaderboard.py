"""The leaderboard page: several configurations ranked, each linked to its episodes, in the static export."""

from __future__ import annotations

import re
from pathlib import Path

from pare.viewer import Catalog, Site, export_site
from tests.viewer.runs import Runs


def test_several_runs_get_a_ranked_leaderboard_linked_to_their_episodes(runs: Runs, tmp_path: Path) -> None:
    site = Site(Catalog.open([runs.models, runs.oracle]))
    export_site(site, tmp_path)
    page = (tmp_path / "leaderboard.html").read_text(encoding="utf-8")
    assert 'href="leaderboard.html"' in (tmp_path / "index.html").read_text(encoding="utf-8")
    body = page[page.index("<tbody>") :]
    labels = re.findall(r'<a href="c/([^/]+)/index.html">([^<]+)</a>\s*<div', body)
    assert [cid for cid, _ in labels] == ["oracle", "models"]  # the oracle succeeds, the models never do
    for cid, _ in labels:
        assert (tmp_path / "c" / cid / "index.html").exists()
        assert f'href="c/{cid}/index.html#success=yes"' in body
    assert "test-user" in body  # the user model of the models' configuration
    assert "pass^2" in body
    assert (tmp_path / "static" / "leaderboard.js").exists()
    assert 'src="static/leaderboard.js"' in page


def test_one_run_has_no_leaderboard(runs: Runs) -> None:
    site = Site(Catalog.open([runs.oracle]))
    assert "leaderboard.html" not in list(site.paths())
    assert site.page("leaderboard.html") is None
    assert "leaderboard.html" not in site.runs_page()
