"""A thinking model's reasoning on the episode page: beside the thought, collapsed."""

from __future__ import annotations

import json
import shutil
from html import unescape
from pathlib import Path

from pare.results.trajectory import read_trajectory
from pare.viewer import Catalog, Site, build_episode
from tests.viewer.runs import Runs

REASONING = 'Maybe wait? Action: {"action": "wait"} — no, the email needs an answer & soon.'
PAGE = "c/models/e/dentist_moves_checkup/run-1.html"


def test_reasoning_is_shown_collapsed_beside_the_thought(runs: Runs, tmp_path: Path) -> None:
    folder = tmp_path / "models"
    shutil.copytree(runs.models, folder)
    record = Catalog.open([folder]).configurations[0].records[("dentist_moves_checkup", 1)]
    assert record.trajectory is not None
    path = folder / record.trajectory
    data = json.loads(path.read_text(encoding="utf-8"))
    user_steps = [step for step in data["steps"] if step["actor"] == "user"]
    user_steps[0]["action"]["reasoning"] = REASONING  # as a thinking model's step records it
    path.write_text(json.dumps(data), encoding="utf-8")

    episode = build_episode(read_trajectory(path), list(record.proposals))
    views = [s for t in episode.turns for s in t.user]
    assert views[0].reasoning == REASONING and views[0].thought  # the thought is still read from the answer
    assert all(s.reasoning is None for s in views[1:])

    page = Site(Catalog.open([folder])).page(PAGE)
    assert page is not None
    html = page.body.decode()
    assert html.count('<details class="reasoning">') == 1
    shown = html.split('<details class="reasoning">', 1)[1].split("</details>", 1)[0]
    assert f"<pre>{REASONING}</pre>" in unescape(shown)
    assert "an answer &amp; soon" in shown  # escaped, as all model text is
    assert html.index('class="thought"') < html.index('<details class="reasoning">')


def test_steps_without_reasoning_show_none(runs: Runs) -> None:
    page = Site(Catalog.open([runs.models])).page(PAGE)
    assert page is not None and 'class="reasoning"' not in page.body.decode()
