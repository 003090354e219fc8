"""Large runs are read by their summary lines only, and a run still being written shows new episodes."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest

from pare.viewer import Catalog, Configuration, Site
from tests.viewer.runs import Runs

EPISODES = 3000


@pytest.fixture
def large(runs: Runs, tmp_path: Path) -> Path:
    """A run folder of :data:`EPISODES` episodes: the model run's records under made-up scenario ids."""
    folder = tmp_path / "large"
    shutil.copytree(runs.models, folder)
    template = json.loads((folder / "episodes.jsonl").read_text(encoding="utf-8").splitlines()[0])
    manifest = json.loads((folder / "manifest.json").read_text(encoding="utf-8"))
    scenarios = {f"scenario_{n:04d}": template["scenario_hash"] for n in range(EPISODES // 2)}
    manifest["plan"] = {"runs": 2, "scenarios": scenarios}
    (folder / "manifest.json").write_text(json.dumps(manifest), encoding="utf-8")
    lines = [
        json.dumps({**template, "scenario_id": scenario, "run": run, "success": n % 3 == 0})
        for n, scenario in enumerate(scenarios)
        for run in (1, 2)
    ]
    (folder / "episodes.jsonl").write_text("\n".join(lines) + "\n", encoding="utf-8")
    return folder


def test_a_large_run_is_listed_without_opening_a_trajectory(
    large: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    opened: list[str] = []
    real = Configuration.trajectory

    def counting(self: Configuration, record):  # type: ignore[no-untyped-def]
        opened.append(record.scenario_id)
        return real(self, record)

    monkeypatch.setattr(Configuration, "trajectory", counting)
    site = Site(Catalog.open([large]))
    for path in ("index.html", "c/large/index.html", "c/large/rows.js"):
        page = site.page(path)
        assert page is not None and page.body
    rows = site.page("c/large/rows.js")
    assert rows is not None and rows.body.count(b'"href"') == EPISODES
    assert opened == []
    page = site.page("c/large/e/scenario_0042/run-2.html")
    assert page is not None and b"scenario_0042" in page.body
    assert opened == ["scenario_0042"]


def test_a_run_being_written_shows_its_new_episodes(runs: Runs, tmp_path: Path) -> None:
    folder = tmp_path / "models"
    shutil.copytree(runs.models, folder)
    site = Site(Catalog.open([folder]))
    configuration = site.catalog.configurations[0]
    before = len(configuration.records)
    first = json.loads((folder / "episodes.jsonl").read_text(encoding="utf-8").splitlines()[0])
    with (folder / "episodes.jsonl").open("a", encoding="utf-8") as episodes:
        episodes.write(json.dumps({**first, "run": 3}) + "\n")
    assert len(configuration.records) == before + 1
    assert site.page(f"c/models/e/{first['scenario_id']}/run-3.html") is not None
