"""Episodes on worker processes, one per core (``pare run --backend processes``).

The simulation is pure Python: one process plays on one core however many episodes it interleaves. Runs
bound by PARE's own work rather than by waiting on models (the oracle, scripted actors, a fast local
model) finish sooner when every core plays episodes. Each worker process receives the run's configuration
and scenarios once, then plays one episode per task (with its own model clients, retrying infrastructure
failures like the local backend) and returns the record and the trajectory; this process stores each as it
arrives, so resume, the store's guarantees and reports are exactly those of a local run. Episodes go out
longest expected first, at most ``concurrency`` workers, never more than there are cores. Each episode's
trajectory is the one the local backend gives it; only the order of the lines in ``episodes.jsonl``
follows the order in which episodes finish.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from concurrent.futures import FIRST_COMPLETED, Future, ProcessPoolExecutor, wait
from concurrent.futures.process import BrokenProcessPool
from dataclasses import dataclass
from pathlib import Path

from pare.bench.processes import available_cores, start_method
from pare.bench.records import EpisodeRecord
from pare.bench.runconfig import RunConfig
from pare.bench.runner import (
    REPORT_INTERVAL_S,
    EpisodeOutput,
    EpisodePlan,
    LongestFirst,
    ProgressSink,
    play_apart,
    report_written,
)
from pare.bench.store import RunStore
from pare.errors import UserInputError
from pare.scenarios.model import Scenario

QUEUED_PER_WORKER = 2
"""Episodes handed to the pool per worker, so that a worker never waits while this process stores."""


@dataclass(frozen=True, slots=True)
class _Task:
    """An episode to play, naming its scenario (each worker holds the scenarios already)."""

    scenario_id: str
    run: int
    seed: int
    scenario_hash: str


class _Worker:
    """What each worker process keeps between its tasks."""

    config: RunConfig
    run_dir: Path
    scenarios: Mapping[str, Scenario]


def _start_worker(config: RunConfig, run_dir: str, scenarios: Mapping[str, Scenario]) -> None:
    _Worker.config, _Worker.run_dir, _Worker.scenarios = config, Path(run_dir), scenarios


def _play(task: _Task) -> tuple[str, EpisodeOutput | str]:
    """One task in a worker (see :func:`~pare.bench.runner.play_apart`)."""
    plan = EpisodePlan(_Worker.scenarios[task.scenario_id], task.run, task.seed, task.scenario_hash)
    return play_apart(plan, _Worker.config, _Worker.run_dir)


def worker_count(config: RunConfig) -> int:
    """Worker processes for ``config``: one per core, at most its concurrency."""
    return max(1, min(available_cores(), config.concurrency))


def run_processes(
    plans: Sequence[EpisodePlan], config: RunConfig, store: RunStore, progress: ProgressSink
) -> list[EpisodeRecord]:
    """Play ``plans`` on worker processes and store each result as it arrives."""
    written: list[EpisodeRecord] = []
    if not plans:
        return written
    workers = worker_count(config)
    scenarios = {plan.scenario.id: plan.scenario for plan in plans}
    queue = LongestFirst(plans, store.records.values())
    pending: dict[Future[tuple[str, EpisodeOutput | str]], EpisodePlan] = {}
    pool = ProcessPoolExecutor(
        max_workers=workers,
        mp_context=start_method(),
        initializer=_start_worker,
        initargs=(config, str(store.path.resolve()), scenarios),
    )
    try:
        while True:
            while len(pending) < workers * QUEUED_PER_WORKER and queue:
                plan = queue.pop()
                task = _Task(plan.scenario.id, plan.run, plan.seed, plan.scenario_hash)
                pending[pool.submit(_play, task)] = plan
            if not pending:
                break
            # with a timeout, so episodes stored meanwhile are reported while the workers play on
            done, _ = wait(pending, timeout=REPORT_INTERVAL_S, return_when=FIRST_COMPLETED)
            report_written(store, progress, written)
            for future in sorted(done, key=lambda f: pending[f].key):  # a fixed order among simultaneous ones
                plan = pending.pop(future)
                try:
                    status, value = future.result()
                except BrokenProcessPool:
                    raise UserInputError(
                        f"a worker process died while playing {plan.scenario.id} run {plan.run} (killed, or "
                        "out of memory?); every episode finished before is recorded: run the same command "
                        "again to resume"
                    ) from None
                if status == "error":
                    assert isinstance(value, str)
                    raise UserInputError(value)
                assert isinstance(value, EpisodeOutput)
                queue.learn(value.record)
                store.append(value.record, value.trajectory)
                report_written(store, progress, written)
        store.flush()
        report_written(store, progress, written)
    finally:  # finished, an error or Ctrl-C: start nothing more, and leave no worker behind
        pool.shutdown(wait=True, cancel_futures=True)
    return written
