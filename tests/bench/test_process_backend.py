"""``--backend processes``: episodes on worker processes, stored exactly as a local run stores them."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import pytest

from pare.bench.process_backend import worker_count
from pare.bench.runconfig import build_config
from pare.bench.runner import run_benchmark
from pare.bench.store import load_run
from pare.cli import main
from tests.scenarios.helpers import to_yaml
from tests.scenarios.test_references import _creates_then_edits

SMOKE = ["dentist_moves_checkup", "five_a_side_kickoff_moved", "dad_printer_ink_from_note"]
NOISY = {"world": {"noise_rate_per_minute": 3.0, "tool_failure_probability": 0.2}}


def _config(output: Path, **extra: Any) -> Any:
    return build_config({"scenarios": {"ids": SMOKE}, "runs": 2, "output": str(output), **NOISY, **extra})


def _stored(folder: Path) -> tuple[dict[str, bytes], dict[tuple[str, int], dict[str, Any]]]:
    trajectories = {
        str(path.relative_to(folder)): path.read_bytes() for path in (folder / "trajectories").rglob("*.json")
    }
    records = {}
    for line in (folder / "episodes.jsonl").read_text().splitlines():
        record = json.loads(line)
        record.pop("wall_s")  # measured, not simulated
        records[(record["scenario_id"], record["run"])] = record
    return trajectories, records


def test_workers_store_what_a_local_run_stores(tmp_path: Path) -> None:
    run_benchmark(_config(tmp_path / "local"))
    summary = run_benchmark(_config(tmp_path / "processes", backend="processes", concurrency=2))
    assert (summary.planned, summary.complete) == (6, 6)
    assert _stored(tmp_path / "processes") == _stored(tmp_path / "local")


def test_a_run_on_workers_resumes_and_extends(tmp_path: Path) -> None:
    run_benchmark(_config(tmp_path / "run", backend="processes", concurrency=2))
    again = run_benchmark(_config(tmp_path / "run", backend="processes", concurrency=2, runs=3))
    assert (again.skipped, again.complete) == (6, 3)
    assert len(load_run(tmp_path / "run").records) == 9


def test_a_configuration_mistake_in_a_worker_stops_the_run_with_its_message(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    broken = _creates_then_edits("${made.event_id}")  # the new event's bare id has no fields
    folder = tmp_path / "scenarios"
    folder.mkdir()
    (folder / "tiny_reply.yaml").write_text(to_yaml(broken))
    arguments = ["run", "--scenario-path", str(folder), "--backend", "processes", "-j", "2", "--no-progress"]
    assert main([*arguments, "-o", str(tmp_path / "run")]) == 2
    assert "${made.event_id}: the result of 'made' has no 'event_id'" in capsys.readouterr().err


def test_workers_are_one_per_core_at_most_the_concurrency() -> None:
    assert worker_count(build_config({"concurrency": 1})) == 1
    assert 1 <= worker_count(build_config({"concurrency": 64})) <= 64
