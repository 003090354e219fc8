"""Damaged run and sweep folders give `pare report` and `pare plot` a clear error, never a traceback."""

from __future__ import annotations

import json
import shutil
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest

from pare.cli import main

Damage = Callable[[Path], Any]


@pytest.fixture(scope="module")
def sound_run(tmp_path_factory: pytest.TempPathFactory) -> Path:
    folder = tmp_path_factory.mktemp("sound") / "run"
    assert (
        main(["run", "-s", "dentist_moves_checkup", "--runs", "2", "-o", str(folder), "--no-progress"]) == 0
    )
    return folder


def _manifest(folder: Path) -> dict[str, Any]:
    data: dict[str, Any] = json.loads((folder / "manifest.json").read_text())
    return data


def _first_record(folder: Path) -> dict[str, Any]:
    data: dict[str, Any] = json.loads((folder / "episodes.jsonl").read_text().splitlines()[0])
    return data


def _set_manifest(**changes: Any) -> Damage:
    return lambda f: (f / "manifest.json").write_text(json.dumps({**_manifest(f), **changes}))


def _set_record(**changes: Any) -> Damage:
    return lambda f: (f / "episodes.jsonl").write_text(json.dumps({**_first_record(f), **changes}) + "\n")


def _replace_with_folder(name: str) -> Damage:
    def damage(folder: Path) -> None:
        (folder / name).unlink()
        (folder / name).mkdir()

    return damage


DAMAGE: dict[str, tuple[Damage, str]] = {
    "manifest not JSON": (
        lambda f: (f / "manifest.json").write_text("{not json"),
        "cannot read the manifest",
    ),
    "manifest a list": (lambda f: (f / "manifest.json").write_text("[1, 2]"), "not a pare run manifest"),
    "manifest not UTF-8": (
        lambda f: (f / "manifest.json").write_bytes(b"\xff\xfe{}"),
        "cannot read the manifest",
    ),
    "manifest a folder": (_replace_with_folder("manifest.json"), "cannot read the manifest"),
    "manifest of a newer format": (
        _set_manifest(format=9),
        "manifest format 9, but this pare reads format 1",
    ),
    "plan not a plan": (_set_manifest(plan="everything"), "is not a run plan"),
    "plan with negative runs": (_set_manifest(plan={"runs": -2, "scenarios": {}}), "is not a run plan"),
    "sweep point not a mapping": (_set_manifest(sweep_point=[1]), "'sweep_point' is not a mapping"),
    "episodes not UTF-8": (lambda f: (f / "episodes.jsonl").write_bytes(b"\xff\xfe\x00\n"), "not utf-8"),
    "episodes a folder": (_replace_with_folder("episodes.jsonl"), "cannot read the episodes file"),
    "a line that is not JSON": (
        lambda f: (f / "episodes.jsonl").write_text("hello\n" + json.dumps(_first_record(f)) + "\n"),
        "episodes.jsonl:1: not an episode record",
    ),
    "a record of a newer format": (_set_record(format=2), "record format 2"),
    "NaN in a record": (_set_record(goal_rate=float("nan")), "finite number"),
    "a record of the wrong shape": (_set_record(goals=[1], turns="many"), "not an episode record"),
}


@pytest.mark.parametrize("damage", DAMAGE, ids=list(DAMAGE))
@pytest.mark.parametrize("command", ["report", "report-json", "plot"])
def test_damaged_run_folder_is_a_clear_error(
    sound_run: Path, tmp_path: Path, damage: str, command: str, capsys: pytest.CaptureFixture[str]
) -> None:
    folder = tmp_path / "run"
    shutil.copytree(sound_run, folder)
    make_damage, expected = DAMAGE[damage]
    make_damage(folder)
    argv = {
        "report": ["report", str(folder)],
        "report-json": ["report", str(folder), "--format", "json"],
        "plot": ["plot", str(folder), "-o", str(tmp_path / "plots")],
    }[command]
    assert main(argv) == 2
    said = " ".join(capsys.readouterr().err.split()).lower()
    assert "error:" in said and expected in said


def test_a_sweep_whose_description_is_damaged_is_a_clear_error(
    sound_run: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    sweep = tmp_path / "sweep"
    shutil.copytree(sound_run, sweep / "point-1")
    (sweep / "sweep.json").write_text("{broken")
    assert main(["report", str(sweep)]) == 2
    assert "error:" in capsys.readouterr().err
