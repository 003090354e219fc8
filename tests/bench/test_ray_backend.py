"""``pare run --backend ray`` stores the same episodes as the local backend (oracle run, no models)."""

from __future__ import annotations

from pathlib import Path

import pytest

from pare.cli import main
from pare.results.records import EpisodeRecord
from pare.results.run_folder import load_run

ray = pytest.importorskip("ray", reason="Ray is an optional extra (pip install 'pare[ray]')")

SCENARIOS = ("dentist_moves_checkup", "five_a_side_kickoff_moved", "sister_gift_jacket_size")
RUNS = 2


def command(output: Path, *extra: str) -> list[str]:
    argv = ["run", "--output", str(output), "--no-progress", "--runs", str(RUNS)]
    for scenario in SCENARIOS:
        argv += ["-s", scenario]
    return argv + list(extra)


def comparable(record: EpisodeRecord) -> dict[str, object]:
    return record.model_dump(exclude={"wall_s"})


def files(run_dir: Path) -> dict[str, bytes]:
    return {
        str(path.relative_to(run_dir)): path.read_bytes()
        for path in sorted((run_dir / "trajectories").rglob("*.json"))
    }


def test_the_ray_backend_stores_what_the_local_backend_stores(tmp_path: Path) -> None:
    assert not ray.is_initialized()  # the backend starts (and stops) a local Ray itself
    assert main(command(tmp_path / "ray", "--backend", "ray", "--concurrency", "4")) == 0
    assert not ray.is_initialized()
    assert main(command(tmp_path / "local")) == 0

    with_ray, local = load_run(tmp_path / "ray"), load_run(tmp_path / "local")
    assert len(with_ray.records) == len(SCENARIOS) * RUNS
    assert all(record.complete for record in with_ray.records)
    assert [comparable(r) for r in with_ray.records] == [comparable(r) for r in local.records]
    assert files(tmp_path / "ray") == files(tmp_path / "local")
    assert len(files(tmp_path / "ray")) == len(SCENARIOS) * RUNS


def test_ray_workers_resolve_a_policy_by_its_import_path(tmp_path: Path) -> None:
    # only the name travels to the workers: each imports the module and builds its own assistant
    policy = ["--assistant-policy", "tests.bench.custom_policies:dentist_assistant"]
    assert main(command(tmp_path / "ray", "--backend", "ray", *policy)) == 0
    assert main(command(tmp_path / "local", *policy)) == 0

    with_ray, local = load_run(tmp_path / "ray"), load_run(tmp_path / "local")
    assert with_ray.manifest["policies"]["assistant"] == "tests.bench.custom_policies:dentist_assistant"
    assert [comparable(r) for r in with_ray.records] == [comparable(r) for r in local.records]
    assert [r.success for r in with_ray.records if r.scenario_id == "dentist_moves_checkup"] == [True, True]
    assert files(tmp_path / "ray") == files(tmp_path / "local")
