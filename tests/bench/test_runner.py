"""Many episodes into a run folder: the offline oracle run, resume after a kill, failures, refusals."""

from __future__ import annotations

import json
import math
import os
import random
import signal
import subprocess
import sys
import time
from pathlib import Path
from types import SimpleNamespace
from typing import Any

import pytest

import pare.bench.runner as runner_module
from pare.bench.build import EpisodePlan
from pare.bench.runconfig import build_config
from pare.bench.runner import EpisodeOutput, run_benchmark
from pare.bench.store import RunStore
from pare.cli import main
from pare.errors import ProviderUnavailable, UserInputError
from pare.results.records import EpisodeRecord
from pare.results.run_folder import EPISODES, MANIFEST, load_run, read_records
from pare.results.trajectory import read_trajectory
from pare.scenarios import library
from tests.scenarios.helpers import base, to_yaml

SMOKE = ["dentist_moves_checkup", "five_a_side_kickoff_moved", "dad_printer_ink_from_note"]


def _config(output: Path, **extra: Any) -> Any:
    return build_config({"scenarios": {"ids": SMOKE}, "runs": 2, "output": str(output), **extra})


def _trajectories(folder: Path) -> dict[str, bytes]:
    return {
        str(path.relative_to(folder)): path.read_bytes()
        for path in sorted((folder / "trajectories").rglob("*.json"))
    }


def test_oracle_run_records_every_episode(tmp_path: Path) -> None:
    summary = run_benchmark(_config(tmp_path / "run"))
    assert (summary.planned, summary.skipped, summary.complete) == (6, 0, 6)
    loaded = load_run(tmp_path / "run")
    assert len(loaded.records) == 6 and all(r.complete and r.success for r in loaded.records)
    assert loaded.planned == [(s, r) for s in sorted(SMOKE) for r in (1, 2)]
    for record in loaded.records:
        trajectory = read_trajectory(tmp_path / "run" / str(record.trajectory))
        assert trajectory.scenario_id == record.scenario_id and trajectory.run == record.run
        assert trajectory.outcome.success is True
        assert record.proposals and record.proposals[0].decision == "accept"
    manifest = loaded.manifest
    assert manifest["label"] == "oracle"
    assert set(manifest["plan"]["scenarios"]) == set(SMOKE)
    assert manifest["provenance"]["pare"] and manifest["provenance"]["python"]
    assert "litellm" in manifest["provenance"]["packages"]


def test_rerunning_resumes_without_repeating(tmp_path: Path) -> None:
    run_benchmark(_config(tmp_path / "run"))
    again = run_benchmark(_config(tmp_path / "run"))
    assert (again.skipped, again.complete) == (6, 0)
    assert len(read_records(tmp_path / "run" / EPISODES)) == 6
    extended = run_benchmark(_config(tmp_path / "run", runs=3))  # more runs extend the same store
    assert (extended.skipped, extended.complete) == (6, 3)
    assert len(load_run(tmp_path / "run").records) == 9
    assert len(json.loads((tmp_path / "run" / MANIFEST).read_text())["sessions"]) == 3


def test_concurrency_does_not_change_trajectories(tmp_path: Path) -> None:
    noisy = {"world": {"noise_rate_per_minute": 3.0, "tool_failure_probability": 0.2}}
    run_benchmark(_config(tmp_path / "one", concurrency=1, **noisy))
    run_benchmark(_config(tmp_path / "many", concurrency=6, **noisy))
    assert _trajectories(tmp_path / "one") == _trajectories(tmp_path / "many")


def test_a_different_configuration_is_refused(tmp_path: Path) -> None:
    run_benchmark(_config(tmp_path / "run"))
    with pytest.raises(UserInputError) as caught:
        run_benchmark(_config(tmp_path / "run", protocol={"max_turns": 4}))
    assert "protocol.max_turns: 10 -> 4" in str(caught.value)


def test_a_changed_scenario_is_refused(tmp_path: Path) -> None:
    folder = tmp_path / "scenarios"
    folder.mkdir()
    data = base()
    (folder / "tiny_reply.yaml").write_text(to_yaml(data))
    config = build_config({"scenarios": {"paths": [str(folder)]}, "runs": 1, "output": str(tmp_path / "run")})
    run_benchmark(config)
    data["title"] = "A different title"
    (folder / "tiny_reply.yaml").write_text(to_yaml(data))
    with pytest.raises(UserInputError, match="would not be comparable: tiny_reply"):
        run_benchmark(config)


def test_a_folder_that_is_not_a_run_is_refused(tmp_path: Path) -> None:
    (tmp_path / "notes.txt").write_text("mine")
    with pytest.raises(UserInputError, match="not a PARE run folder"):
        run_benchmark(_config(tmp_path))


def test_two_writers_are_refused(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    import pare.bench.store as store_module

    monkeypatch.setattr(store_module, "LOCK_WAIT_S", 0.1)  # no need to wait for a killed run's writer
    config = _config(tmp_path / "run")
    scenarios = {scenario_id: library()[scenario_id] for scenario_id in SMOKE}
    with (
        RunStore.open(tmp_path / "run", config, scenarios),
        pytest.raises(UserInputError, match="another 'pare run'"),
    ):
        run_benchmark(config)


def test_infrastructure_failures_are_retried_then_recorded_as_missing_coverage(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    real = runner_module.play_episode
    calls: dict[tuple[str, int], int] = {}

    async def flaky(plan: EpisodePlan, config: Any, models: Any, attempt: int = 1) -> EpisodeOutput:
        calls[plan.key] = calls.get(plan.key, 0) + 1
        if plan.scenario.id == "dentist_moves_checkup":
            raise ProviderUnavailable("provider kept answering 503")
        if plan.scenario.id == "five_a_side_kickoff_moved" and attempt == 1:
            raise ProviderUnavailable("one 503")
        return await real(plan, config, models, attempt)

    monkeypatch.setattr(runner_module, "play_episode", flaky)
    monkeypatch.setattr(runner_module, "RETRY_PAUSE_S", 0.0)
    summary = run_benchmark(_config(tmp_path / "run", episode_retries=2))
    by_key = {r.key: r for r in summary.records}
    assert calls[("dentist_moves_checkup", 1)] == 3  # the first try and two retries
    failed = by_key[("dentist_moves_checkup", 1)]
    assert failed.status == "failed" and failed.failure is not None
    assert failed.failure.kind == "provider_unavailable" and "503" in failed.failure.message
    assert (
        by_key[("five_a_side_kickoff_moved", 1)].complete
        and by_key[("five_a_side_kickoff_moved", 1)].attempts == 2
    )
    assert len(summary.failed) == 2

    monkeypatch.setattr(runner_module, "play_episode", real)  # the provider is back: resume fills the gaps
    resumed = run_benchmark(_config(tmp_path / "run", episode_retries=2))
    assert (resumed.skipped, resumed.complete) == (4, 2)
    loaded = load_run(tmp_path / "run")
    assert len(loaded.records) == 6 and all(r.complete for r in loaded.records)


def test_a_bug_in_one_episode_does_not_stop_the_run(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    real = runner_module.arun_episode

    async def broken(scenario: Any, *args: Any, **kwargs: Any) -> Any:
        if scenario.id == "dad_printer_ink_from_note":
            raise KeyError("a bug")
        return await real(scenario, *args, **kwargs)

    monkeypatch.setattr(runner_module, "arun_episode", broken)
    summary = run_benchmark(_config(tmp_path / "run"))
    failed = [r for r in summary.records if not r.complete]
    assert {r.scenario_id for r in failed} == {"dad_printer_ink_from_note"}
    assert failed[0].failure is not None and failed[0].failure.kind == "internal_error"
    assert "KeyError: 'a bug'" in failed[0].failure.message and failed[0].attempts == 1


def test_a_configuration_mistake_stops_the_run(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.delenv("PARE_NO_SUCH_KEY", raising=False)
    config = _config(
        tmp_path / "run",
        models={
            "assistant": {
                "model": "m",
                "api_base": "http://127.0.0.1:9/v1",
                "api_key_env": "PARE_NO_SUCH_KEY",
            }
        },
    )
    with pytest.raises(UserInputError, match="PARE_NO_SUCH_KEY"):
        run_benchmark(config)
    assert not (tmp_path / "run").exists()  # checked before anything was made


def test_a_torn_last_line_is_dropped_and_rerun(tmp_path: Path) -> None:
    run_benchmark(_config(tmp_path / "run"))
    file = tmp_path / "run" / EPISODES
    lines = file.read_text().splitlines(keepends=True)
    file.write_text("".join(lines[:-1]) + lines[-1][: len(lines[-1]) // 2])  # killed mid-write
    assert len(read_records(file)) == 5
    resumed = run_benchmark(_config(tmp_path / "run"))
    assert (resumed.skipped, resumed.complete) == (5, 1)
    records = read_records(file)
    assert len(records) == 6 and len({r.key for r in records}) == 6


def test_kill_and_resume_loses_and_repeats_nothing(tmp_path: Path) -> None:
    """Kill a real `pare run` process mid-run (SIGKILL: no cleanup at all), then run the same command."""
    reference = tmp_path / "reference"
    killed = tmp_path / "killed"
    args = ["run", "--runs", "12", "--set", "world.noise_rate_per_minute=2", "--no-progress", "-j", "4"]
    assert main([*args, "-o", str(reference)]) == 0
    total = len(read_records(reference / EPISODES))
    assert total == 12 * len(library())

    env = {**os.environ, "PYTHONUNBUFFERED": "1"}
    process = subprocess.Popen(
        [sys.executable, "-m", "pare", *args, "-o", str(killed)],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
        env=env,
    )
    episodes = killed / EPISODES
    deadline = time.monotonic() + 60
    try:
        while time.monotonic() < deadline:
            if episodes.exists() and episodes.read_text().count("\n") >= 30:
                break
            if process.poll() is not None:
                break
            time.sleep(0.002)
    finally:
        process.send_signal(signal.SIGKILL)
        process.wait()
    before = len(read_records(episodes))
    assert 30 <= before < total, "the run must be killed mid-way for this test to mean anything"

    assert main([*args, "-o", str(killed)]) == 0
    records = read_records(episodes)
    assert len(records) == total
    assert len({r.key for r in records}) == total
    assert all(r.complete for r in records)
    assert _trajectories(killed) == _trajectories(reference)


def test_cli_run_prints_the_summary_and_where_results_are(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setenv("COLUMNS", "200")
    assert main(["run", "--split", "smoke", "--runs", "1", "-o", str(tmp_path / "run"), "--no-progress"]) == 0
    out = capsys.readouterr().out
    assert "oracle: 5 episodes run" in out
    assert "100.0%" in out
    assert f"pare report {tmp_path / 'run'}" in out


def test_cli_reports_bad_options_clearly(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["run", "-s", "no_such_scenario", "-o", str(tmp_path / "run"), "--no-progress"]) == 2
    assert "no scenario 'no_such_scenario'" in capsys.readouterr().err
    assert main(["run", "--set", "protocol.max_turns=0", "-o", str(tmp_path / "run2"), "--no-progress"]) == 2
    assert "protocol.max_turns" in capsys.readouterr().err


def test_records_round_trip(tmp_path: Path) -> None:
    run_benchmark(_config(tmp_path / "run"))
    for line in (tmp_path / "run" / EPISODES).read_text().splitlines():
        record = EpisodeRecord.model_validate_json(line)
        assert record.model_dump_json() == line


def test_manifest_masks_secret_looking_settings_but_keeps_variable_names(tmp_path: Path) -> None:
    from pare.agents.models.secrets import redact_secrets

    public = {"api_key_env": "OPENAI_API_KEY", "extra": {"extra_headers": {"Authorization": "Bearer abc"}}}
    assert redact_secrets(public) == {
        "api_key_env": "OPENAI_API_KEY",
        "extra": {"extra_headers": {"Authorization": "***"}},
    }
    config = _config(tmp_path / "run")
    scenarios = {scenario_id: library()[scenario_id] for scenario_id in SMOKE}
    with RunStore.open(tmp_path / "run", config, scenarios) as store:
        assert store.manifest["identity_hash"] == config.identity_hash()


def test_episodes_run_longest_expected_first_once_a_scenario_was_seen() -> None:
    from pare.bench.runner import LongestFirst, plan_episodes

    config = build_config({"scenarios": {"ids": SMOKE}, "runs": 3})
    scenarios = {scenario_id: library()[scenario_id] for scenario_id in SMOKE}
    plans = plan_episodes(config, scenarios)  # run-major: run 1 of each (sorted), then run 2, then run 3
    dad, dentist, five = sorted(SMOKE)

    def finished(scenario_id: str, run: int, seconds: float) -> EpisodeRecord:
        return EpisodeRecord(
            scenario_id=scenario_id, run=run, status="complete", scenario_hash="h", seed=0, wall_s=seconds
        )

    # an earlier session finished dentist run 1 (5 s): the two scenarios never seen go first, in plan order
    queue = LongestFirst([p for p in plans if p.key != (dentist, 1)], [finished(dentist, 1, 5.0)])
    assert [queue.pop().key for _ in range(2)] == [(dad, 1), (five, 1)]
    queue.learn(finished(five, 1, 1.0))
    queue.learn(finished(dad, 1, 9.0))
    order = [queue.pop().key for _ in range(len(queue))]
    assert order == [(dad, 2), (dad, 3), (dentist, 2), (dentist, 3), (five, 2), (five, 3)]


def _scan_pick(pending: list[tuple[int, Any]], learned: dict[str, list[float]]) -> tuple[int, Any]:
    """The plain rule, by a pass over every pending episode: the longest expected, then earliest planned."""

    def rank(item: tuple[int, Any]) -> tuple[float, int]:
        scenario_id = item[1].scenario.id
        seen = learned[scenario_id]
        expected = sum(seen) / len(seen) if seen else math.inf
        first = min(index for index, plan in pending if plan.scenario.id == scenario_id)
        return (expected, -first)

    return max(pending, key=rank)  # among one scenario's episodes, the first planned


def test_longest_first_picks_what_a_scan_of_every_scenario_picks() -> None:
    """The queue keeps its scenarios in a heap; its picks are those of the plain rule over many random
    plans, earlier finished episodes and timings, ties included."""
    from pare.bench.runner import LongestFirst

    def record(scenario_id: str, run: int, seconds: float, complete: bool = True) -> EpisodeRecord:
        status = "complete" if complete else "failed"
        return EpisodeRecord(
            scenario_id=scenario_id, run=run, status=status, scenario_hash="h", seed=0, wall_s=seconds
        )

    for trial in range(300):
        rng = random.Random(trial)
        ids = [f"s{i:02d}" for i in range(rng.randint(1, 10))]
        plans: list[Any] = [
            SimpleNamespace(scenario=SimpleNamespace(id=s), key=(s, r))
            for r in range(1, rng.randint(1, 4) + 1)
            for s in ids
        ]
        seconds = [0.5, 1.0, 2.0, 3.0]  # few values: many ties
        done = {plan.key for plan in plans if rng.random() < 0.3}
        finished = [record(s, r, rng.choice(seconds), rng.random() < 0.9) for s, r in sorted(done)]
        todo = [plan for plan in plans if plan.key not in done]
        queue = LongestFirst(todo, finished)
        learned = {s: [r.wall_s for r in finished if r.scenario_id == s and r.complete] for s in ids}
        pending = list(enumerate(todo))
        while pending:
            assert len(queue) == len(pending)
            expected = _scan_pick(pending, learned)
            pending.remove(expected)
            assert queue.pop() is expected[1]
            if rng.random() < 0.7:  # it finished (some runs fail)
                finished_now = record(*expected[1].key, rng.choice(seconds), rng.random() < 0.9)
                queue.learn(finished_now)
                if finished_now.complete:
                    learned[finished_now.scenario_id].append(finished_now.wall_s)
        assert not queue
