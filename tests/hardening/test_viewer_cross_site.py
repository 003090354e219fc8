"""While ``pare view`` serves runs, pages of other sites cannot read them: the episodes table is given
only with the server's key (which only the viewer's own pages carry), requests a browser marks as
cross-site are refused, and every answer forbids other origins to load it. The export, opened from disk,
loads its table without any key.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest
from starlette.testclient import TestClient

from pare.cli import main
from pare.viewer import Catalog, Site
from pare.viewer._server import create_app


@pytest.fixture(scope="module")
def run(tmp_path_factory: pytest.TempPathFactory) -> Path:
    folder = tmp_path_factory.mktemp("cross") / "run"
    assert (
        main(["run", "-s", "dentist_moves_checkup", "--runs", "1", "-o", str(folder), "--no-progress"]) == 0
    )
    return folder


def served(run: Path) -> tuple[TestClient, str]:
    """A client of the live app and the rows URL its own configuration page loads."""
    client = TestClient(create_app(Site(Catalog.open([run]))), base_url="http://127.0.0.1")
    page = client.get("/c/run/index.html", headers={"sec-fetch-site": "none", "sec-fetch-mode": "navigate"})
    assert page.status_code == 200
    found = re.search(r'<script src="(rows\.js\?key=[^"]+)"', page.text)
    assert found, "the configuration page loads its rows with the server's key"
    return client, "/c/run/" + found.group(1)


def test_the_viewers_own_page_reads_its_rows(run: Path) -> None:
    client, rows = served(run)
    response = client.get(rows, headers={"sec-fetch-site": "same-origin", "sec-fetch-mode": "no-cors"})
    assert response.status_code == 200 and "dentist_moves_checkup" in response.text
    assert response.headers["cross-origin-resource-policy"] == "same-origin"
    assert response.headers["x-content-type-options"] == "nosniff"


@pytest.mark.parametrize("query", ["", "?key=", "?key=guessed"])
def test_rows_without_the_servers_key_are_refused(run: Path, query: str) -> None:
    client, _ = served(run)
    response = client.get("/c/run/rows.js" + query)
    assert response.status_code == 403 and "dentist" not in response.text


@pytest.mark.parametrize("origin", ["cross-site", "same-site"])
def test_a_load_marked_as_from_another_site_is_refused_even_with_the_key(run: Path, origin: str) -> None:
    client, rows = served(run)
    for path in (rows, "/index.html", "/c/run/index.html"):
        response = client.get(path, headers={"sec-fetch-site": origin, "sec-fetch-mode": "no-cors"})
        assert response.status_code == 403 and "dentist" not in response.text


def test_a_link_followed_from_another_site_opens_the_page(run: Path) -> None:
    client, _ = served(run)
    response = client.get(
        "/index.html", headers={"sec-fetch-site": "cross-site", "sec-fetch-mode": "navigate"}
    )
    assert response.status_code == 200


def test_every_answer_forbids_other_origins(run: Path) -> None:
    client, _ = served(run)
    for path in ("/index.html", "/static/viewer.js", "/c/run/rows.js", "/nothing"):
        assert client.get(path).headers["cross-origin-resource-policy"] == "same-origin"


def test_the_export_loads_its_rows_from_disk_without_a_key(run: Path, tmp_path: Path) -> None:
    site = tmp_path / "site"
    assert main(["view", str(run), "--export", str(site)]) == 0
    page = (site / "c" / "run" / "index.html").read_text(encoding="utf-8")
    assert '<script src="rows.js" defer>' in page and "key=" not in page
    assert "dentist_moves_checkup" in (site / "c" / "run" / "rows.js").read_text(encoding="utf-8")
