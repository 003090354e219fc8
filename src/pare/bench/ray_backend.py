"""Episodes as Ray tasks, for runs larger than one machine (``pare run --backend ray``).

Each episode is one Ray task that plays it (with its own model clients, retrying infrastructure failures
like the local backend) and returns its record and trajectory to the driver; the driver stores each as it
arrives, so resume and reports work exactly as for a local run. At most ``concurrency`` tasks are in
flight. Ray is an optional extra (``pip install "pare-bench[ray]"``).

On a cluster, every node needs PARE installed, and a model-call cache shared between nodes needs
``cache_path`` on a shared file system (or ``cache: off``); on one machine the default cache works.
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from pare.bench.build import EpisodePlan
from pare.bench.run_requests import Learned, RunRequests
from pare.bench.runconfig import RunConfig
from pare.bench.runner import REPORT_INTERVAL_S, LongestFirst, ProgressSink, play_apart, report_written
from pare.bench.store import RunStore
from pare.errors import UserInputError
from pare.install import install_command
from pare.results.records import EpisodeRecord

TASK_CPUS = 0.25
"""CPUs Ray reserves per episode task: episodes mostly wait on model calls, so several share a core."""


def _import_ray() -> Any:
    os.environ.setdefault("RAY_USAGE_STATS_ENABLED", "0")  # no usage report: there may be no network
    try:
        import ray
    except ImportError:
        raise UserInputError(f"--backend ray needs Ray: {install_command('ray')}") from None
    return ray


def play_remote(plan: EpisodePlan, config: RunConfig, run_dir: str, learned: Learned) -> tuple[str, Any]:
    """The body of one Ray task (see :func:`~pare.bench.runner.play_apart`)."""
    return play_apart(plan, config, Path(run_dir), learned)


def run_ray(
    plans: Sequence[EpisodePlan],
    config: RunConfig,
    store: RunStore,
    progress: ProgressSink,
    requests: RunRequests | None = None,
) -> list[EpisodeRecord]:
    """Play ``plans`` as Ray tasks and store each result as it arrives. Each task starts from the
    parameter refusals ``requests`` knows; those it learns come back with its result and are taken in
    (warned about and recorded here: a task's own log does not reach the driver).
    """
    requests = requests or RunRequests.create(config)
    ray = _import_ray()
    started_here = not ray.is_initialized()
    if started_here:
        ray.init(
            address=config.ray_address,
            include_dashboard=False,
            log_to_driver=False,
            configure_logging=False,
        )
    task = ray.remote(num_cpus=TASK_CPUS, max_retries=0)(play_remote)
    written: list[EpisodeRecord] = []
    queue = LongestFirst(plans, store.records.values())
    pending: dict[Any, EpisodePlan] = {}
    run_dir = str(store.path.resolve())
    try:
        while True:
            while len(pending) < config.concurrency and queue:
                plan = queue.pop()
                pending[task.remote(plan, config, run_dir, requests.learned())] = plan
            if not pending:
                break
            # with a timeout, so episodes stored meanwhile are reported while the tasks run on
            ready, _ = ray.wait(list(pending), num_returns=1, timeout=REPORT_INTERVAL_S)
            report_written(store, progress, written)
            for ref in ready:
                pending.pop(ref)
                status, value = ray.get(ref)
                if status == "error":
                    raise UserInputError(value)
                requests.absorb(value.learned)
                queue.learn(value.record)
                store.append(value.record, value.trajectory)
                report_written(store, progress, written)
        store.flush()
        report_written(store, progress, written)
    finally:
        for ref in pending:
            ray.cancel(ref, force=True)
        if started_here:
            ray.shutdown()
    return written
