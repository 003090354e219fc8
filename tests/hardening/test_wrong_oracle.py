"""A scenario file given by path whose own oracle cannot pass is pointed out before the run."""

from __future__ import annotations

from pathlib import Path

import pytest

from pare.cli import main


def _run(scenario: Path, output: Path) -> int:
    return main(
        ["run", "--scenario-path", str(scenario), "--runs", "1", "--output", str(output), "--no-progress"]
    )


def test_a_scenario_whose_oracle_fails_is_warned_about_and_still_run(
    example_scenario: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    text = example_scenario.read_text(encoding="utf-8")
    broken = text.replace("start_datetime: day+3 08:00}, count: 1", "start_datetime: day+3 09:00}, count: 1")
    assert broken != text
    example_scenario.write_text(broken, encoding="utf-8")
    assert _run(example_scenario, tmp_path / "run") == 0
    out = " ".join(capsys.readouterr().out.split())
    assert "warning: the oracle of scenario 'dentist_example' does not pass" in out
    assert "check failed" in out and "pare scenarios check" in out
    assert (tmp_path / "run" / "episodes.jsonl").exists()


def test_a_sound_scenario_file_runs_without_a_warning(
    example_scenario: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    assert _run(example_scenario, tmp_path / "run") == 0
    assert "warning" not in capsys.readouterr().out
