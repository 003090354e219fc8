"""A run pauses and freezes the cyclic collector for speed, and gives the caller's process its collector
back as it was, whether the run succeeds or fails.
"""

from __future__ import annotations

import gc
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path

import pytest

from pare.bench import collector
from pare.bench.runconfig import build_config
from pare.bench.runner import run_benchmark
from pare.errors import UserInputError


@pytest.fixture(autouse=True)
def _restore_collector() -> Iterator[None]:
    enabled = gc.isenabled()
    yield
    gc.unfreeze()
    (gc.enable if enabled else gc.disable)()


def _config(output: Path, **extra: object) -> object:
    scenarios = {"ids": ["dentist_moves_checkup"]}
    return build_config({"scenarios": scenarios, "runs": 1, "output": str(output), **extra})


def test_a_run_leaves_the_collector_as_it_found_it(tmp_path: Path) -> None:
    gc.enable()
    summary = run_benchmark(_config(tmp_path / "on"))  # type: ignore[arg-type]
    assert summary.complete == 1  # played, with the collector paused then frozen
    assert gc.isenabled() and gc.get_freeze_count() == 0

    gc.disable()  # a caller that manages the collector itself keeps it off
    run_benchmark(_config(tmp_path / "off"))  # type: ignore[arg-type]
    assert not gc.isenabled() and gc.get_freeze_count() == 0


def test_a_failing_run_gives_the_collector_back(tmp_path: Path) -> None:
    gc.enable()
    config = _config(tmp_path / "run", scenarios={"ids": ["no_such_scenario"]})
    with pytest.raises(UserInputError):
        run_benchmark(config)  # type: ignore[arg-type]
    assert gc.isenabled() and gc.get_freeze_count() == 0


def test_the_episodes_play_with_the_collector_on_and_the_run_frozen() -> None:
    gc.disable()
    with collector.paused():
        assert not gc.isenabled()
    assert not gc.isenabled()
    gc.enable()
    with collector.paused():
        assert not gc.isenabled()
        held = [object() for _ in range(10)]
    assert gc.isenabled()
    with collector.long_lived_frozen():
        assert gc.isenabled() and gc.get_freeze_count() > len(held)
    assert gc.get_freeze_count() == 0


def test_the_process_keeps_its_exit_code_and_output_when_it_skips_the_last_collection(tmp_path: Path) -> None:
    """``pare`` as a process freezes everything before it exits (skip_final_collection): what it wrote
    and the exit code it gives, 0 for a run and 2 for a mistake, are unchanged by that."""
    done = subprocess.run(
        [
            sys.executable,
            "-m",
            "pare",
            "run",
            "-s",
            "dentist_moves_checkup",
            "--runs",
            "1",
            "--no-progress",
            "-o",
            str(tmp_path / "run"),
        ],
        capture_output=True,
        text=True,
        check=False,
    )
    assert done.returncode == 0, done.stderr
    assert "results:" in done.stdout
    assert (tmp_path / "run" / "episodes.jsonl").read_text().count("\n") == 1
    bad = subprocess.run(
        [sys.executable, "-m", "pare", "run", "-s", "no_such_scenario", "-o", str(tmp_path / "bad")],
        capture_output=True,
        text=True,
        check=False,
    )
    assert bad.returncode == 2 and "no_such_scenario" in bad.stderr


def test_the_gate_in_process_gives_the_collector_back(tmp_path: Path) -> None:
    """The gate freezes what each scenario's self-test leaves (collector.settle) inside the gate's own
    frozen block: the caller's process gets its collector back as it was."""
    from pare.cli import main
    from tests.scenarios.helpers import sound, to_yaml

    scenario = sound()
    (tmp_path / f"{scenario['id']}.yaml").write_text(to_yaml(scenario))
    gc.enable()
    assert main(["scenarios", "check", "-j", "1", str(tmp_path)]) == 0
    assert gc.isenabled() and gc.get_freeze_count() == 0
