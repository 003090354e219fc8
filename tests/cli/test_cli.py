from __future__ import annotations

import subprocess
import sys

import pytest

from pare.apps.registry import phone_apps
from pare.cli import main


def test_apps_lists_every_app_with_its_screens(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["apps"]) == 0
    out = capsys.readouterr().out
    for name in phone_apps():
        assert name in out
    assert "Mailbox" in out and "Agenda" in out and "open_app" in out


def test_apps_show_prints_screens_and_tools(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["apps", "show", "contacts"]) == 0
    out = capsys.readouterr().out
    assert "screen Detail" in out and "start_edit_contact" in out and "contacts__edit_contact" in out
    delete = next(line for line in out.splitlines() if "contacts__delete_contact" in line)
    assert "write, irreversible" in delete  # each write tool says how bad a wrong call is


def test_apps_show_seed_format(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["apps", "show", "calendar", "--seed"]) == 0
    out = capsys.readouterr().out
    assert out.startswith("seed:\n  calendar:\n    events:  # a list of CalendarEvent, each with its")
    assert "start_datetime: time  # required; a time: ISO, an offset from the start" in out


def test_apps_show_mermaid(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["apps", "show", "email", "--mermaid"]) == 0
    out = capsys.readouterr().out
    assert out.startswith("stateDiagram-v2") and "Mailbox --> Detail : open_email" in out


def test_unknown_app_is_a_clear_error(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["apps", "show", "emial"]) == 2
    assert "Unknown app 'emial'. Did you mean 'email'?" in capsys.readouterr().err


def test_bad_option_is_a_usage_error(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["apps", "show", "email", "--bogus"]) == 2
    assert "--bogus" in capsys.readouterr().err


def test_console_script_runs() -> None:
    done = subprocess.run(
        [sys.executable, "-m", "pare", "version"], capture_output=True, text=True, check=False
    )
    assert done.returncode == 0 and done.stdout.strip()


def test_files_has_no_diagram(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["apps", "show", "files"]) == 0
    assert "files__list_directory" in capsys.readouterr().out
    assert main(["apps", "show", "files", "--mermaid"]) == 2
    assert "has no screens" in capsys.readouterr().err


def test_the_command_line_loads_the_library_only_for_commands_that_use_it() -> None:
    """`pare --help` (and every command's registration) imports no apps, scenarios, harness or model
    client: each command imports what it uses when it runs, so the command line starts fast."""
    import subprocess
    import sys

    heavy = (
        "pare.apps",
        "pare.scenarios",
        "pare.env",
        "pare.agents",
        "pare.bench.runner",
        "pare.results.metrics",
        "pare.bench.episode",
        "pydantic",
        "openai",
    )
    code = f"import sys, pare.cli\nprint(sorted(m for m in sys.modules if m.startswith({heavy!r})))\n"
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert done.stdout.strip() == "[]"
