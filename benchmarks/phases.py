"""Where a whole-library oracle run's time goes, phase by phase, in one process.

    python benchmarks/phases.py [--runs 4] [--split full]

Times ``pare run --split full --runs 4`` (the oracle plays both roles) from a fresh interpreter: importing
the command line and the runner, loading the library, then each phase of the episodes (building the
environment, playing the turns, evaluating the goals, snapshots and the state diff, building the typed
trajectory and writing its text, writing to the store), each phase's total over every episode and its
share of the run. Phases are measured by wrapping the functions that do them, so the wrappers' own cost
(well under 1%) is in the figures. Nested phases are listed under the phase they run in. Prints numbers
only; no assertion.
"""

from __future__ import annotations

import argparse
import collections
import contextlib
import functools
import inspect
import io
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

began = time.perf_counter()
import pare.bench.episode as episode_module  # noqa: E402  (timed: the imports are a phase)
import pare.bench.runner as runner_module  # noqa: E402
import pare.bench.store as store_module  # noqa: E402
import pare.cli as cli_module  # noqa: E402
import pare.cli.run_cmd as run_cmd_module  # noqa: E402
import pare.env as env_module  # noqa: E402

# ``pare.scenarios.library`` as an attribute is the function of that name; the module is in sys.modules
library_module = sys.modules["pare.scenarios.library"]
imported = time.perf_counter() - began

totals: collections.Counter[str] = collections.Counter()
calls: collections.Counter[str] = collections.Counter()


def timed(owner: Any, name: str, label: str) -> None:
    """Replace ``owner.name`` by a wrapper that adds its time to ``label``."""
    function: Callable[..., Any] = getattr(owner, name)
    if inspect.iscoroutinefunction(function):

        @functools.wraps(function)
        async def wrapper(*args: Any, **kwargs: Any) -> Any:
            start = time.perf_counter()
            try:
                return await function(*args, **kwargs)
            finally:
                totals[label] += time.perf_counter() - start
                calls[label] += 1

    else:

        @functools.wraps(function)
        def wrapper(*args: Any, **kwargs: Any) -> Any:
            start = time.perf_counter()
            try:
                return function(*args, **kwargs)
            finally:
                totals[label] += time.perf_counter() - start
                calls[label] += 1

    setattr(owner, name, wrapper)


# (label, parent label or None): the order in which they print
PHASES: list[tuple[str, str | None]] = [
    ("load the library", None),
    ("open the store", None),
    ("plan the episodes", None),
    ("episodes (play_episode)", None),
    ("build the environment", "episodes (play_episode)"),
    ("turns", "episodes (play_episode)"),
    ("  of which: end-when-met checks", "turns"),
    ("evaluate the goals (end-when-met ones too)", "episodes (play_episode)"),
    ("snapshots", "episodes (play_episode)"),
    ("state diff", "episodes (play_episode)"),
    ("the typed trajectory", "episodes (play_episode)"),
    ("trajectory to JSON text", "episodes (play_episode)"),
    ("summarise the record", "episodes (play_episode)"),
    ("store.append (write record and trajectory)", None),
    ("print the summary (metrics read back)", None),
]


def instrument() -> None:
    timed(library_module, "load_scenarios", "load the library")
    timed(runner_module, "play_episode", "episodes (play_episode)")
    timed(episode_module, "build_environment", "build the environment")
    timed(episode_module._Episode, "_turns", "turns")
    timed(episode_module._Episode, "_settled", "  of which: end-when-met checks")
    timed(episode_module, "evaluate", "evaluate the goals (end-when-met ones too)")
    timed(env_module.Environment, "snapshot", "snapshots")
    timed(episode_module, "state_changes", "state diff")
    timed(episode_module.EpisodeResult, "trajectory", "the typed trajectory")
    timed(runner_module, "write_trajectory", "trajectory to JSON text")
    timed(runner_module, "summarize", "summarise the record")
    timed(store_module.RunStore, "append", "store.append (write record and trajectory)")
    timed(store_module.RunStore, "open", "open the store")
    timed(runner_module, "plan_episodes", "plan the episodes")
    timed(run_cmd_module, "print_summary", "print the summary (metrics read back)")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=4)
    parser.add_argument("--split", default="full")
    options = parser.parse_args()
    instrument()
    with tempfile.TemporaryDirectory(prefix="pare-phases-") as scratch:
        start = time.perf_counter()
        arguments = ["run", "--split", options.split, "--runs", str(options.runs), "--no-progress"]
        with contextlib.redirect_stdout(io.StringIO()):
            code = cli_module.main([*arguments, "-o", str(Path(scratch) / "run")])
        command = time.perf_counter() - start
    if code != 0:
        raise SystemExit(f"pare run exited with {code}")
    whole = imported + command
    episodes = calls["episodes (play_episode)"]
    print(f"pare run --split {options.split} --runs {options.runs}: {episodes} episodes, {whole:.2f} s")
    print(f"{'phase':50s} {'seconds':>8s} {'share':>6s} {'ms/episode':>11s}")
    rows = [("import the CLI and the runner", None, imported)] + [
        (label, parent, totals[label]) for label, parent in PHASES
    ]
    for label, parent, seconds in rows:
        indent = "  " if parent is not None and parent != "episodes (play_episode)" else ""
        indent = indent + ("  " if parent is not None else "")
        per_episode = f"{seconds / episodes * 1000:11.3f}" if episodes and label != "load the library" else ""
        print(f"{indent + label:50s} {seconds:8.3f} {seconds / whole:6.1%} {per_episode}")
    accounted = imported + totals["load the library"] + totals["episodes (play_episode)"]
    for label in ("store.append (write record and trajectory)", "open the store", "plan the episodes"):
        accounted += totals[label]
    accounted += totals["print the summary (metrics read back)"]
    rest = whole - accounted
    print(f"{'everything else (settings, closing the store...)':50s} {rest:8.3f} {rest / whole:6.1%}")


if __name__ == "__main__":
    main()
