"""A full disk outside the run store: the static export, ``pare generate`` and the model-call cache each
stop with a one-line error that names the file, never a traceback, and a cache write the disk refuses is
never filed as the episode's ``internal_error``.

The disk is made full by making the write raise what the system raises then (``ENOSPC``).
"""

from __future__ import annotations

import errno
import json
import pathlib
import sqlite3
from pathlib import Path
from typing import Any

import pytest

from pare.agents.models.cache import ModelCallCache
from pare.cli import main
from pare.testing import ChatServer, proactive_play
from pare.testing.generation import ScriptedGeneration
from tests.generate.conftest import BENCH, example_answers
from tests.hardening.conftest import KEY_VARIABLE


def full_disk_under(monkeypatch: pytest.MonkeyPatch, folder: Path, *, after: int = 0) -> None:
    """Writes of files under ``folder`` fail with ENOSPC once ``after`` of them succeeded."""
    done = {"writes": 0}
    for name in ("write_bytes", "write_text"):
        original = getattr(pathlib.Path, name)

        def write(self: Path, data: Any, *args: Any, _original: Any = original, **kwargs: Any) -> int:
            if self.resolve().is_relative_to(folder.resolve()):
                if done["writes"] >= after:
                    raise OSError(errno.ENOSPC, "No space left on device", str(self))
                done["writes"] += 1
            result: int = _original(self, data, *args, **kwargs)
            return result

        monkeypatch.setattr(pathlib.Path, name, write)


def one_line_error(capsys: pytest.CaptureFixture[str]) -> str:
    err = capsys.readouterr().err
    assert "Traceback" not in err
    return " ".join(err.split())


def test_an_export_onto_a_full_disk_is_a_clear_error(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    run = tmp_path / "run"
    assert main(["run", "-s", "dentist_moves_checkup", "--runs", "1", "-o", str(run), "--no-progress"]) == 0
    site = tmp_path / "site"
    full_disk_under(monkeypatch, site, after=3)
    assert main(["view", str(run), "--export", str(site)]) == 2
    err = one_line_error(capsys)
    assert "cannot write the site" in err and "No space left on device" in err and "3 of its files" in err


def test_generate_onto_a_full_disk_is_a_clear_error(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    library = tmp_path / "library"
    library.mkdir()
    name = "book_club_pick_paperback.yaml"
    (library / name).write_text((BENCH / name).read_text(encoding="utf-8"), encoding="utf-8")
    out = tmp_path / "out"
    answers = {stage: [text] for stage, text in example_answers().items()}
    with ChatServer(ScriptedGeneration({1: answers})) as server:
        argv = ["generate", "--apps", "email,calendar", "-n", "1", "-o", str(out), "--cache", "off"]
        argv += ["--endpoint", server.base_url, "--library", str(library), "--no-progress"]
        full_disk_under(monkeypatch, out, after=2)  # the manifest and a transcript fit, then the disk is full
        assert main([*argv, "--model", "pare-generator"]) == 2
    err = one_line_error(capsys)
    assert "cannot write it: No space left on device" in err and str(out) in err and "resume" in err
    assert not list(out.rglob("*.tmp"))  # no half-written file left behind


def test_a_cache_write_onto_a_full_disk_stops_the_run_naming_the_cache(
    tmp_path: Path,
    example_scenario: Path,
    monkeypatch: pytest.MonkeyPatch,
    capsys: pytest.CaptureFixture[str],
) -> None:
    def full(self: ModelCallCache, *args: Any) -> bool:
        raise sqlite3.OperationalError("database or disk is full")

    monkeypatch.setattr(ModelCallCache, "_insert", full)
    output = tmp_path / "run"
    argv = [
        "run",
        "--output",
        str(output),
        "--no-progress",
        "--runs",
        "1",
        "--scenario-path",
        str(example_scenario),
    ]
    with ChatServer(proactive_play()) as server:
        argv += ["--assistant-model", "a", "--assistant-endpoint", server.base_url]
        argv += ["--user-model", "u", "--user-endpoint", server.base_url]
        for role in ("user", "assistant"):
            argv += ["--set", f"models.{role}.api_key_env={KEY_VARIABLE}"]
        assert main(argv) == 2
    err = one_line_error(capsys)
    assert "model_calls.sqlite" in err and "database or disk is full" in err and "resume" in err
    episodes = output / "episodes.jsonl"
    records = (
        [json.loads(line) for line in episodes.read_text(encoding="utf-8").splitlines()]
        if episodes.exists()
        else []
    )
    assert all((record.get("failure") or {}).get("kind") != "internal_error" for record in records)
