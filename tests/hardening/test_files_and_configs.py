"""Hostile scenario files, run configurations and settings: each is refused quickly with a clear error that
names the problem (and the file and line where there is one), never a traceback, a hang or a crash.
"""

from __future__ import annotations

import os
import subprocess
import sys
import time
from pathlib import Path

import pytest

from pare.cli import main
from pare.yaml_source import MAX_DEPTH, MAX_EXPANDED_NODES, MAX_FILE_BYTES

BOMB = """\
a: &a ["lol", "lol", "lol", "lol", "lol", "lol", "lol", "lol", "lol"]
b: &b [*a, *a, *a, *a, *a, *a, *a, *a, *a]
c: &c [*b, *b, *b, *b, *b, *b, *b, *b, *b]
d: &d [*c, *c, *c, *c, *c, *c, *c, *c, *c]
e: &e [*d, *d, *d, *d, *d, *d, *d, *d, *d]
f: &f [*e, *e, *e, *e, *e, *e, *e, *e, *e]
g: &g [*f, *f, *f, *f, *f, *f, *f, *f, *f]
h: &h [*g, *g, *g, *g, *g, *g, *g, *g, *g]
i: &i [*h, *h, *h, *h, *h, *h, *h, *h, *h]
"""


def refused(capsys: pytest.CaptureFixture[str], argv: list[str]) -> str:
    """Run the command line; it must exit 2 (a mistake in what it was given) without a traceback."""
    started = time.perf_counter()
    code = main(argv)
    elapsed = time.perf_counter() - started
    err = capsys.readouterr().err
    assert code == 2, err
    assert "Traceback" not in err
    assert elapsed < 10, f"took {elapsed:.1f}s to refuse"
    return " ".join(err.split())  # rich wraps long lines


# -- scenario files ---------------------------------------------------------------------------------------
def test_an_alias_bomb_in_a_scenario_is_refused_with_its_line(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    path = tmp_path / "bomb.yaml"
    path.write_text(BOMB, encoding="utf-8")
    err = refused(capsys, ["scenarios", "check", str(path)])
    assert f"{path}:" in err and f"more than {MAX_EXPANDED_NODES} values" in err


def test_an_alias_inside_what_it_names_is_refused(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    path = tmp_path / "loop.yaml"
    path.write_text("id: x\nseed: &loop\n  again: *loop\n", encoding="utf-8")
    err = refused(capsys, ["scenarios", "check", str(path)])
    assert f"{path}:2" in err and "alias refers to a collection that contains it" in err


def test_nesting_just_past_the_limit_is_refused(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    path = tmp_path / "deep.yaml"
    levels = MAX_DEPTH + 1
    path.write_text("id: x\nseed: " + "[" * levels + "]" * levels + "\n", encoding="utf-8")
    err = refused(capsys, ["scenarios", "check", str(path)])
    assert f"{path}:2" in err and f"nested more than {MAX_DEPTH} levels" in err


def test_very_deep_nesting_is_refused_at_its_line(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    # Whether PARE's own depth check or the YAML parser's refuses first depends on the parser's version;
    # what a user relies on is the refusal (exit 2) naming the file and the line, not whose words say it.
    path = tmp_path / "deep.yaml"
    path.write_text("id: x\nseed: " + "[" * 1_000 + "]" * 1_000 + "\n", encoding="utf-8")
    err = refused(capsys, ["scenarios", "check", str(path)])
    assert f"{path}:2" in err


def test_nesting_that_would_overflow_the_c_parser_is_refused_not_a_crash(tmp_path: Path) -> None:
    # In a child process: a regression here would kill the interpreter (libyaml's composer recurses in C).
    path = tmp_path / "abyss.yaml"
    path.write_text("[" * 100_000 + "]" * 100_000, encoding="utf-8")
    done = subprocess.run(
        [sys.executable, "-m", "pare", "scenarios", "check", str(path)],
        capture_output=True,
        text=True,
        timeout=60,
        check=False,
    )
    assert done.returncode == 2, done.stderr
    assert f"{path}:1" in " ".join(done.stderr.split())  # refused with its place, whoever words it
    assert "Traceback" not in done.stderr


def test_only_regular_files_are_read(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    err = refused(capsys, ["scenarios", "check", "/dev/zero"])
    assert "/dev/zero" in err and "not a regular file" in err

    fifo = tmp_path / "pipe.yaml"
    os.mkfifo(fifo)  # opening it would wait for a writer forever
    err = refused(capsys, ["scenarios", "check", str(fifo)])
    assert "not a regular file" in err


def test_files_that_are_too_large_or_not_text_are_refused(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    large = tmp_path / "large.yaml"
    large.write_bytes(b"# " + b"x" * MAX_FILE_BYTES + b"\n")
    assert "larger than 4 MiB" in refused(capsys, ["scenarios", "check", str(large)])

    latin = tmp_path / "latin.yaml"
    latin.write_bytes("id: x\ntitle: caf\u00e9\n".encode("latin-1"))
    assert "line 2: it is not UTF-8" in refused(capsys, ["scenarios", "check", str(latin)])


# -- run configurations and settings ----------------------------------------------------------------------
def test_an_alias_bomb_in_a_run_configuration_is_refused(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    config = tmp_path / "run.yaml"
    indented = "".join(f"      {line}\n" for line in BOMB.splitlines())
    config.write_text(f"models:\n  assistant:\n    model: m\n    extra:\n{indented}", encoding="utf-8")
    err = refused(capsys, ["run", "-c", str(config), "--output", str(tmp_path / "out")])
    assert f"{config}:" in err and "aliases expand" in err
    assert not (tmp_path / "out").exists()


def test_a_set_value_is_read_within_the_same_bounds(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    err = refused(capsys, ["run", "--set", "seed=" + "[" * 1_000 + "]" * 1_000, "-o", str(tmp_path / "o")])
    assert f"nested more than {MAX_DEPTH} levels" in err


@pytest.mark.parametrize(
    ("argv", "expected"),
    [
        (["--noise-rate", "inf"], "world.noise_rate_per_minute"),
        (["--noise-rate", "nan"], "world.noise_rate_per_minute"),
        (["--noise-rate", "1e9"], "less than or equal to 60"),
        (["--set", "runs=1.0e+20"], "runs: Unable to parse input string as an integer"),
        (["--set", "runs=1.0e+6"], "less than or equal to 1000"),
        (["--set", "protocol.max_turns=1000000000"], "less than or equal to 1000"),
        (["--set", "concurrency=1.0e+12"], "less than or equal to 4096"),
        (["--set", "protocol.turn_duration=0s"], "protocol.turn_duration"),
        (["--set", "seed=-1"], "greater than or equal to 0"),
    ],
)
def test_absurd_numbers_are_configuration_mistakes(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], argv: list[str], expected: str
) -> None:
    err = refused(capsys, ["run", "--output", str(tmp_path / "out"), *argv])
    assert expected in err
    assert not (tmp_path / "out").exists()
