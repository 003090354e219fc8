"""The viewer over damaged trajectories: every page renders, a damaged episode's page says what is wrong,
and an export writes the whole site.

A seeded fuzz damages the trajectories of real runs (the oracle and model-backed actors) the ways a file
gets damaged: a key dropped, a value of the wrong type, the text cut short, a format number this PARE
does not know. It is bounded (a fixed number of variants) and deterministic (a fixed seed).
"""

from __future__ import annotations

import json
import random
import shutil
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
from starlette.testclient import TestClient

from pare.cli import main
from pare.results.run_folder import load_run
from pare.viewer import Catalog, Site
from pare.viewer._paths import slug
from pare.viewer._server import create_app
from tests.viewer.runs import KEY_VARIABLE, Runs, make_runs

VARIANTS = 240
SEED = 20261207
WRONG_VALUES: tuple[Any, ...] = (None, 0, -1, 1.5, "", "x", [], {}, [None], {"": None}, True)


@pytest.fixture(scope="module")
def runs(tmp_path_factory: pytest.TempPathFactory) -> Runs:
    with pytest.MonkeyPatch.context() as patch:
        patch.setenv(KEY_VARIABLE, "not-a-real-key")
        return make_runs(tmp_path_factory.mktemp("fuzz"), runs=1)


def places(value: Any, path: tuple[Any, ...] = ()) -> Iterator[tuple[Any, ...]]:
    """Every path to a value inside ``value`` (keys and list indexes)."""
    items = value.items() if isinstance(value, dict) else enumerate(value) if isinstance(value, list) else ()
    for key, item in items:
        yield (*path, key)
        yield from places(item, (*path, key))


def parent_of(data: Any, path: tuple[Any, ...]) -> Any:
    for key in path[:-1]:
        data = data[key]
    return data


def damage(text: str, rng: random.Random) -> tuple[str, str]:
    """One damaged version of a trajectory's text, and how it was damaged."""
    kind = rng.choice(["drop", "retype", "retype", "truncate", "format"])
    if kind == "truncate":
        return text[: rng.randrange(1, len(text))], kind
    data = json.loads(text)
    if kind == "format":
        data["format"] = rng.choice([0, 3, 99, "1", None])
        return json.dumps(data), kind
    path = rng.choice(list(places(data)))
    parent = parent_of(data, path)
    if kind == "drop":
        del parent[path[-1]]
    else:
        parent[path[-1]] = rng.choice(WRONG_VALUES)
    return json.dumps(data), f"{kind} {'/'.join(map(str, path))}"


def episode_pages(site: Site) -> list[str]:
    return [path for path in site.paths() if "/e/" in path]


@pytest.mark.parametrize("which", ["oracle", "models"])
def test_every_damaged_trajectory_gets_a_page(runs: Runs, tmp_path: Path, which: str) -> None:
    folder = tmp_path / which
    shutil.copytree(getattr(runs, which), folder)
    files = sorted(str(record.trajectory) for record in load_run(folder).records if record.trajectory)
    originals = {name: (folder / name).read_text(encoding="utf-8") for name in files}
    site = Site(Catalog.open([folder]))
    pages = dict(zip(sorted(files), sorted(episode_pages(site)), strict=True))
    client = TestClient(create_app(site), base_url="http://127.0.0.1")
    rng = random.Random(SEED)
    shown = damaged = 0
    for number in range(VARIANTS):
        name = rng.choice(files)
        text, how = damage(originals[name], rng)
        (folder / name).write_text(text, encoding="utf-8")
        response = client.get("/" + pages[name])
        assert response.status_code == 200, f"variant {number} ({how}) of {name}: {response.status_code}"
        page = response.text
        damaged += 'class="bad problem"' in page
        shown += 'id="goals"' in page
        if how == "format":
            assert "trajectory format" in page, f"variant {number}: a foreign format shown as this one"
        (folder / name).write_text(originals[name], encoding="utf-8")
    assert shown and damaged  # both kinds of page happened: the fuzz reached the renderer


def test_an_export_over_damaged_trajectories_writes_every_page(runs: Runs, tmp_path: Path) -> None:
    folder = tmp_path / "models"
    shutil.copytree(runs.models, folder)
    rng = random.Random(SEED)
    files = sorted(folder.glob("trajectories/*/run-*.json"))
    for file in files:
        text, _ = damage(file.read_text(encoding="utf-8"), rng)
        file.write_text(text, encoding="utf-8")
    (files[0]).write_text(json.dumps({"format": 7, "steps": []}), encoding="utf-8")
    site = tmp_path / "site"
    assert main(["view", str(folder), "--export", str(site)]) == 0
    written = sorted(site.glob("c/*/e/*/run-*.html"))
    assert len(written) == len(files)
    first = site.joinpath(
        *written[0].relative_to(site).parts[:2], "e", slug(files[0].parent.name), "run-1.html"
    )
    assert "trajectory format 7" in first.read_text(encoding="utf-8")
