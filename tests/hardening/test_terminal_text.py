"""Text that did not come from PARE reaches the terminal as text: rich markup in it is shown as written
(never a crash, a style or a live link) and its control characters are shown as visible escapes (never
obeyed: no hidden text, cleared screen or window title).

The commands run with colour forced on, as at a terminal, so PARE's own styles are written as escape
sequences and the tests can tell them from those the hostile text tried to smuggle in.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

from pare.cli import main
from pare.generate.folder import OUTCOMES
from pare.terminal_text import markup_safe, printable
from pare.testing import ChatServer, Reply, completion, failure, proactive_play
from tests.generate.conftest import ScriptedGenerator, example_answers, library
from tests.hardening.conftest import KEY_VARIABLE

__all__ = ["library"]

MARKUP = "a [/] b [link=https://evil.example]click[/link] [bold red]loud"
"""Markup that crashes rich (``[/]`` closes nothing), makes a live link, or styles what follows."""
CONTROLS = "\x1b[8mhidden\x1b[0m \x1b]0;pwned\x07 \x1b[2J\x1b[H \x9b31m \r\u202eevil"
"""Concealed text, a window title, a cleared screen, a C1 CSI, a carriage return, a right-to-left override."""
HOSTILE = f"{MARKUP} {CONTROLS} :smile:"
OBEYED = ("\x1b[8m", "\x1b]", "\x1b[2J", "\x1b[H", "\x9b", "\x07", "\r", "\u202e", "\U0001f604")
"""What the terminal would act on (or an emoji code turned into one); none may be written."""


def yaml_quoted(text: str) -> str:
    """``text`` as a YAML double-quoted scalar (JSON's escapes are YAML's)."""
    return json.dumps(text)


@pytest.fixture(autouse=True)
def colour_terminal(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("FORCE_COLOR", "1")
    monkeypatch.delenv("NO_COLOR", raising=False)
    monkeypatch.setenv("COLUMNS", "400")


def assert_shown_as_text(output: str) -> None:
    """Every hostile part is on screen as written, none is obeyed."""
    for sequence in OBEYED:
        assert sequence not in output, f"{sequence!r} reached the terminal"
    flat = _without_styles(output)
    assert "a [/] b [link=https://evil.example]click[/link] [bold red]loud" in flat
    assert "\\x1b[8mhidden" in flat and "\\x1b]0;pwned\\x07" in flat and "\\x9b31m" in flat
    assert "\\u202eevil" in flat and ":smile:" in flat


def _without_styles(output: str) -> str:
    """``output`` without the SGR sequences PARE's own styles are written as (and without line folds)."""
    import re

    return re.sub(r"\x1b\[[0-9;]*m", "", output)


def hostile_scenario(folder: Path, example_scenario: Path) -> Path:
    """The worked example with hostile text in its title and story."""
    text = example_scenario.read_text(encoding="utf-8")
    title = "title: The dentist moves tomorrow's check-up"
    assert title in text
    lines = text.replace(title, f"title: {yaml_quoted(HOSTILE)}").splitlines(keepends=True)
    start = lines.index("story: >\n")
    end = next(i for i in range(start + 1, len(lines)) if not lines[i].startswith("  "))
    text = "".join([*lines[:start], f"story: {yaml_quoted(HOSTILE)}\n", *lines[end:]])
    path = folder / "dentist_example.yaml"
    folder.mkdir(parents=True, exist_ok=True)
    path.write_text(text, encoding="utf-8")
    return path


# -- the helper -------------------------------------------------------------------------------------------
def test_control_characters_become_visible_and_layout_is_kept() -> None:
    shown = printable("a\x1b[2Jb\x00c\x7f\x85\x9b\u202e\ud800")
    assert shown == "a\\x1b[2Jb\\x00c\\x7f\\x85\\x9b\\u202e\ufffd"
    assert printable("line one\n\tindented, caf\u00e9, \u65e5\u672c, \U0001f600") == (
        "line one\n\tindented, caf\u00e9, \u65e5\u672c, \U0001f600"
    )
    assert markup_safe("[/] [link=x]y") != "[/] [link=x]y"  # escaped for rich, shown the same (below)


# -- generated candidates under review ----------------------------------------------------------------------
def test_review_shows_a_hostile_candidate_as_text(
    tmp_path: Path, example_scenario: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    folder = tmp_path / "candidates"
    hostile_scenario(folder, example_scenario)
    (folder / "b[bold]x[link=y]\x1b[2J.yaml").write_text("id: broken\n", encoding="utf-8")  # does not load
    assert main(["scenarios", "review", str(folder), "--no-input"]) == 0
    out = capsys.readouterr().out
    assert_shown_as_text(out)
    assert "b[bold]x[link=y]\\x1b[2J" in _without_styles(out)
    assert "gate:" in out  # the candidate was shown to the end


def test_show_list_and_check_show_a_hostile_scenario_as_text(
    tmp_path: Path, example_scenario: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    path = hostile_scenario(tmp_path / "files", example_scenario)
    assert main(["scenarios", "show", str(path)]) == 0
    assert_shown_as_text(capsys.readouterr().out)
    assert main(["scenarios", "list", str(path)]) == 0
    out = capsys.readouterr().out
    assert not any(sequence in out for sequence in OBEYED)
    assert "[/] b [link=https://evil.example]" in _without_styles(out).replace("\n", "")


def test_an_error_quoting_a_file_shows_its_control_characters(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    assert main(["run", "--scenario", "dentist\x1b]0;pwned\x07\x1b[2J", "-o", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err
    assert "\x1b]0;" not in err and "\x1b[2J" not in err and "\x07" not in err
    assert "dentist\\x1b]0;pwned\\x07\\x1b[2J" in err


# -- run labels and model names -----------------------------------------------------------------------------
def test_a_hostile_run_label_is_shown_as_text_after_the_run_and_in_the_report(
    tmp_path: Path, example_scenario: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    output = tmp_path / "run"
    argv = ["run", "--scenario-path", str(example_scenario), "--runs", "1", "-o", str(output)]
    assert main([*argv, "--set", f"name={yaml_quoted(HOSTILE)}"]) == 0  # with the progress bar
    captured = capsys.readouterr()
    assert_shown_as_text(captured.out)
    live = [sequence for sequence in OBEYED if sequence != "\r"]  # a progress bar redraws its line with \r
    assert [sequence for sequence in live if sequence in captured.err] == []
    assert "a [/] b [link=https://evil.example]" in _without_styles(captured.err)
    for command in (["report", str(output)], ["report", str(output), "-o", str(tmp_path / "report.txt")]):
        assert main(command) == 0
    assert_shown_as_text(capsys.readouterr().out)
    written = (tmp_path / "report.txt").read_text(encoding="utf-8")
    assert not any(sequence in written for sequence in OBEYED)
    for output_format in ("markdown", "csv", "latex", "json"):
        assert main(["report", str(output), "-f", output_format]) == 0
        out = capsys.readouterr().out
        assert not any(sequence in out for sequence in OBEYED), output_format
    assert json.loads(out)["configurations"][0]["label"] == HOSTILE  # JSON's escapes: the same label


@pytest.fixture
def server() -> Iterator[ChatServer]:
    with ChatServer(proactive_play()) as chat:
        yield chat


def test_a_hostile_model_name_is_shown_as_text_in_the_plan_the_roles_and_the_summary(
    tmp_path: Path, example_scenario: Path, server: ChatServer, capsys: pytest.CaptureFixture[str]
) -> None:
    argv = ["run", "--output", str(tmp_path / "run"), "--no-progress", "--runs", "1"]
    argv += ["--scenario-path", str(example_scenario), "--user-endpoint", server.base_url]
    argv += ["--user-model", HOSTILE, "--assistant-model", "a", "--assistant-endpoint", server.base_url]
    for role in ("user", "assistant"):
        argv += ["--set", f"models.{role}.api_key_env={KEY_VARIABLE}"]
    assert main([*argv, "--dry-run"]) == 0
    assert_shown_as_text(capsys.readouterr().out)
    assert main(argv) == 0  # the judge note names the user's model after the run
    assert_shown_as_text(capsys.readouterr().out)


def test_doctor_shows_a_hostile_answer_and_model_name_as_text(capsys: pytest.CaptureFixture[str]) -> None:
    def hostile(body: dict[str, Any]) -> Reply:
        return completion(HOSTILE, 12, 1, model=str(body.get("model")))

    with ChatServer(hostile) as chat:
        argv = ["doctor", "--user-model", HOSTILE, "--user-endpoint", chat.base_url]
        assert main([*argv, "--set", f"models.user.api_key_env={KEY_VARIABLE}"]) == 0
    out = capsys.readouterr().out
    assert not any(sequence in out for sequence in OBEYED)
    assert "[/] b [link=https://evil.example]" in _without_styles(out)


# -- the generator's problems ------------------------------------------------------------------------------
def test_generate_shows_the_generator_s_mistakes_as_text(
    tmp_path: Path, library: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    answers = example_answers()
    apps = "apps: [email, calendar]"
    assert apps in answers["story"]
    story = answers["story"].replace(apps, f"apps: [email, calendar, {yaml_quoted(HOSTILE)}]")
    folder = tmp_path / "out"
    argv = ["generate", "--apps", "email,calendar", "-n", "1", "-o", str(folder), "--no-progress"]
    argv += ["--library", str(library), "--model", "pare-generator", "--retries", "0"]
    scripts = {1: {**{stage: [text] for stage, text in answers.items()}, "story": [story]}}
    with ChatServer(ScriptedGenerator(scripts)) as chat:
        assert main([*argv, "--endpoint", chat.base_url]) == 0
    outcome = json.loads((folder / OUTCOMES).read_text(encoding="utf-8"))
    assert outcome["status"] == "failed" and any("[/]" in problem for problem in outcome["problems"])
    out = capsys.readouterr().out
    assert not any(sequence in out for sequence in OBEYED)
    assert "[/] b [link=https://evil.example]" in _without_styles(out).replace("\n", "")


# -- providers' words in logged warnings -----------------------------------------------------------------
def test_a_provider_s_error_quoted_in_a_retry_warning_is_shown_as_text(
    tmp_path: Path, example_scenario: Path
) -> None:
    play = proactive_play()
    answered: list[int] = []

    def first_fails(body: dict[str, Any]) -> Reply:
        answered.append(1)
        return failure(500, HOSTILE) if len(answered) == 1 else play(body)

    with ChatServer(first_fails) as chat:
        argv = ["run", "--output", str(tmp_path / "run"), "--no-progress", "--runs", "1"]
        argv += ["--scenario-path", str(example_scenario), "--user-model", "u", "--assistant-model", "a"]
        for role in ("user", "assistant"):
            argv += ["--set", f"models.{role}.api_base={chat.base_url}"]
            argv += [
                "--set",
                f"models.{role}.api_key_env={KEY_VARIABLE}",
                "--set",
                f"models.{role}.max_retries=2",
            ]
            argv += [
                "--set",
                f"models.{role}.retry_initial_s=0.001",
                "--set",
                f"models.{role}.retry_max_s=0.01",
            ]
        # A child process: the command's own logging, as at a terminal (pytest installs its handlers).
        done = subprocess.run(
            [sys.executable, "-m", "pare", *argv],
            capture_output=True,
            text=True,
            timeout=120,
            check=False,
            env={**os.environ, KEY_VARIABLE: "sk-pare-hardening-test"},
        )
    assert done.returncode == 0, done.stderr[-2_000:]
    assert "attempt 1 failed" in done.stderr
    assert not any(sequence in done.stderr for sequence in OBEYED)
    assert "\\x1b[8mhidden" in done.stderr and "[/] b [link=https://evil.example]" in done.stderr
