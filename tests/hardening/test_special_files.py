"""Files of a run folder and generated candidates that are not regular UTF-8 files (a FIFO, a device, bytes
that are not text) are refused with a message that names them: never read (a FIFO would hang the reader
for good, ``/dev/zero`` would fill its memory), never a traceback.

Every command runs in a child process with a time limit, so a regression fails the test instead of
hanging it.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from collections.abc import Callable
from pathlib import Path

import pytest

from pare.cli import main

LIMIT_S = 60
Special = Callable[[Path], None]


def fifo(path: Path) -> None:
    path.unlink(missing_ok=True)
    os.mkfifo(path)


def dev_zero(path: Path) -> None:
    path.unlink(missing_ok=True)
    path.symlink_to("/dev/zero")


def not_utf8(path: Path) -> None:
    path.write_bytes(b'{"steps": ["caf\xe9"]}\n')


SPECIAL: dict[str, tuple[Special, str]] = {
    "fifo": (fifo, "not a regular file"),
    "/dev/zero": (dev_zero, "not a regular file"),
    "not UTF-8": (not_utf8, "not utf-8"),
}


def pare(*argv: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-m", "pare", *argv], capture_output=True, text=True, timeout=LIMIT_S, check=False
    )


def said(done: subprocess.CompletedProcess[str]) -> str:
    return " ".join((done.stdout + done.stderr).split()).lower()


@pytest.fixture(scope="module")
def sound_run(tmp_path_factory: pytest.TempPathFactory) -> Path:
    folder = tmp_path_factory.mktemp("sound") / "run"
    assert (
        main(["run", "-s", "dentist_moves_checkup", "--runs", "2", "-o", str(folder), "--no-progress"]) == 0
    )
    return folder


@pytest.mark.parametrize("special", SPECIAL, ids=list(SPECIAL))
@pytest.mark.parametrize("name", ["manifest.json", "episodes.jsonl"])
def test_report_refuses_a_special_run_file_by_name(
    sound_run: Path, tmp_path: Path, name: str, special: str
) -> None:
    folder = tmp_path / "run"
    shutil.copytree(sound_run, folder)
    make, expected = SPECIAL[special]
    make(folder / name)
    done = pare("report", str(folder))
    assert done.returncode == 2 and "Traceback" not in done.stderr
    assert name in said(done) and expected in said(done)


@pytest.mark.parametrize("special", SPECIAL, ids=list(SPECIAL))
def test_the_viewer_shows_a_special_trajectory_as_a_problem_and_writes_the_rest(
    sound_run: Path, tmp_path: Path, special: str
) -> None:
    folder = tmp_path / "run"
    shutil.copytree(sound_run, folder)
    make, expected = SPECIAL[special]
    if special == "/dev/zero":  # a link out of the run folder is refused before its target is looked at
        expected = "leads outside"
    make(folder / "trajectories" / "dentist_moves_checkup" / "run-1.json")
    site = tmp_path / "site"
    done = pare("view", str(folder), "--export", str(site))
    assert done.returncode == 0, done.stderr
    pages = sorted(site.glob("c/*/e/dentist_moves_checkup/run-*.html"))
    assert [page.name for page in pages] == ["run-1.html", "run-2.html"]
    damaged = " ".join(pages[0].read_text(encoding="utf-8").split()).lower()
    assert expected in damaged and "run-1.json" in damaged
    assert "not a regular file" not in pages[1].read_text(encoding="utf-8")


def test_review_lists_special_candidates_as_unreadable(tmp_path: Path) -> None:
    folder = tmp_path / "candidates"
    folder.mkdir()
    fifo(folder / "piped.yaml")
    dev_zero(folder / "zeros.yaml")
    (folder / "latin.yaml").write_bytes("id: latin\ntitle: caf\u00e9\n".encode("latin-1"))
    done = pare("scenarios", "review", str(folder))
    assert done.returncode == 0 and "Traceback" not in done.stderr, done.stderr
    text = said(done)
    for name in ("piped", "zeros", "latin"):
        assert name in text
    assert "not a regular file" in text and "not utf-8" in text
    refused = pare("scenarios", "review", str(folder), "--reject", "piped", "--reason", "odd")
    assert refused.returncode == 2 and "piped.yaml" in said(refused) and "not a regular file" in said(refused)
    assert (folder / "piped.yaml").exists()  # nothing moved
