"""Spreading independent CPU-bound work (the gate's scenarios) over several processes.

The simulation is pure Python, so one process uses one core however many episodes it interleaves; the
self-test of a library (thousands of scripted episodes, no model to wait for) is bound by that core. Work
items go to a pool of worker processes as pickles and come back in their original order, so output does
not depend on which worker finished first.
"""

from __future__ import annotations

import multiprocessing
import os
from collections.abc import Callable, Iterator, Sequence
from concurrent.futures import ProcessPoolExecutor
from multiprocessing.context import BaseContext
from typing import TypeVar

from pare.errors import UserInputError

Item = TypeVar("Item")
Result = TypeVar("Result")


def available_cores() -> int:
    """The cores this process may run on (its CPU affinity where the platform tells, else all)."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # macOS and Windows have no affinity call
        return os.cpu_count() or 1


def resolve_jobs(jobs: int | None) -> int:
    """How many processes to use: ``jobs`` when given (at least 1), else one per available core."""
    if jobs is None or jobs == 0:
        return available_cores()
    if jobs < 0:
        raise UserInputError(f"--jobs must be 0 (one per core) or a positive number of processes, got {jobs}")
    return jobs


def start_method() -> BaseContext:
    """Workers are started from a clean server process (forkserver) where the platform has it, else
    spawned: never forked from this process, whose threads (a progress bar, an HTTP client) could hold
    a lock at the moment of the fork and leave the child stuck on it.
    """
    methods = multiprocessing.get_all_start_methods()
    return multiprocessing.get_context("forkserver" if "forkserver" in methods else "spawn")


def map_in_processes(
    function: Callable[[Item], Result], items: Sequence[Item], jobs: int
) -> Iterator[Result]:
    """``function`` applied to each item, in the items' order, on up to ``jobs`` processes.

    ``function`` must be a module-level function and items and results picklable. With one job or one
    item the work stays in this process (no pool to start). An exception raised for an item is raised
    here when its turn comes; the items not started yet are then cancelled.
    """
    if jobs <= 1 or len(items) <= 1:
        yield from map(function, items)
        return
    with ProcessPoolExecutor(max_workers=min(jobs, len(items)), mp_context=start_method()) as pool:
        futures = [pool.submit(function, item) for item in items]
        try:
            for future in futures:
                yield future.result()
        finally:  # an error, Ctrl-C or a consumer that stopped early: start nothing more
            for future in futures:
                future.cancel()
