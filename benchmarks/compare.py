"""Compare one figure between two checkouts, interleaved, so that a change shows its effect on a noisy
machine.

    python benchmarks/compare.py --base main --head WORKTREE [--figure help] [-n 7]
    python benchmarks/compare.py --base HEAD~3 --head HEAD --figure library
    python benchmarks/compare.py --base main --head . --cmd "python benchmarks/episode.py --quiet"

``--base`` and ``--head`` each name a commit (anything ``git rev-parse`` takes) or a folder holding a
checkout (``.`` is the working tree, with its uncommitted changes). A commit is checked out into a
temporary worktree. Each repetition runs the figure once in each checkout, alternating which goes first,
with ``PYTHONPATH`` pointing at that checkout's ``src`` and the checkout as working directory, so both see
the same load on the machine. Printed: every time, the medians, and head / base.

Figures (whole processes, wall time):

* ``help``: ``python -m pare --help``.
* ``import``: ``python -c "import pare.cli"``.
* ``library``: ``pare run`` of the whole library, 4 runs per scenario, the oracle playing (a fresh
  folder each time).
* ``gate``: ``pare scenarios check`` of the whole library.
* ``kernel``, ``episode``, ``scenarios``, ``runner``: the benchmark script of that name (its own numbers
  are printed by the script and not parsed; its wall time is compared).

``--cmd`` times any shell command instead. Prints numbers only; no assertion.
"""

from __future__ import annotations

import argparse
import os
import shlex
import statistics
import subprocess
import sys
import tempfile
import time
from contextlib import ExitStack
from pathlib import Path

FIGURES: dict[str, str] = {
    "help": "{python} -m pare --help",
    "import": '{python} -c "import pare.cli"',
    "library": "{python} -m pare run --split full --runs 4 --no-progress -o {scratch}/run",
    "gate": "{python} -m pare scenarios check",
    "kernel": "{python} benchmarks/kernel.py",
    "episode": "{python} benchmarks/episode.py",
    "scenarios": "{python} benchmarks/scenarios.py",
    "runner": "{python} benchmarks/runner.py",
}


def checkout(spec: str, stack: ExitStack) -> Path:
    """The folder of a checkout: ``spec`` itself when it is a folder, else a temporary worktree of the
    commit it names (removed on exit)."""
    folder = Path(spec)
    if folder.is_dir() and (folder / "src" / "pare").is_dir():
        return folder.resolve()
    commit = subprocess.run(
        ["git", "rev-parse", "--verify", f"{spec}^{{commit}}"], capture_output=True, text=True, check=False
    )
    if commit.returncode != 0:
        raise SystemExit(f"error: '{spec}' is neither a checkout folder nor a commit")
    place = Path(stack.enter_context(tempfile.TemporaryDirectory(prefix="pare-compare-"))) / "tree"
    subprocess.run(["git", "worktree", "add", "--detach", str(place), commit.stdout.strip()], check=True,
                   capture_output=True)  # fmt: skip
    stack.callback(subprocess.run, ["git", "worktree", "remove", "--force", str(place)], check=False)
    return place


def time_once(command: str, tree: Path) -> float:
    """Wall seconds of ``command`` run in ``tree`` with that tree's code (output discarded)."""
    environment = {**os.environ, "PYTHONPATH": str(tree / "src")}
    with tempfile.TemporaryDirectory(prefix="pare-compare-run-") as scratch:
        text = command.format(python=shlex.quote(sys.executable), scratch=scratch)
        began = time.perf_counter()
        done = subprocess.run(text, shell=True, cwd=tree, env=environment, capture_output=True, check=False)
        seconds = time.perf_counter() - began
    if done.returncode not in (0, 1):
        tail = done.stderr.decode(errors="replace").strip().splitlines()[-3:]
        raise SystemExit(f"error: '{text}' in {tree} exited {done.returncode}: {' / '.join(tail)}")
    return seconds


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--base", required=True, help="A commit or a checkout folder.")
    parser.add_argument("--head", default=".", help="A commit or a checkout folder (default: this tree).")
    parser.add_argument("--figure", choices=sorted(FIGURES), default="help")
    parser.add_argument("--cmd", help="Time this shell command instead of a figure ({python} is replaced).")
    parser.add_argument("-n", "--repetitions", type=int, default=7)
    parser.add_argument("--warmup", type=int, default=1, help="Untimed runs of each side first.")
    args = parser.parse_args()
    command = args.cmd or FIGURES[args.figure]
    with ExitStack() as stack:
        sides = {"base": checkout(args.base, stack), "head": checkout(args.head, stack)}
        for _ in range(args.warmup):
            for tree in sides.values():
                time_once(command, tree)
        times: dict[str, list[float]] = {"base": [], "head": []}
        for repetition in range(args.repetitions):
            order = ["base", "head"] if repetition % 2 == 0 else ["head", "base"]
            for side in order:
                times[side].append(time_once(command, sides[side]))
        print(f"figure: {args.cmd or args.figure}   repetitions: {args.repetitions} (interleaved)")
        for side in ("base", "head"):
            shown = " ".join(f"{t:.3f}" for t in times[side])
            median = statistics.median(times[side])
            print(f"{side:>4} {sides[side]!s:<40} median {median:.3f} s   [{shown}]")
        ratio = statistics.median(times["head"]) / statistics.median(times["base"])
        print(f"head / base: {ratio:.2f} ({(1 - ratio) * 100:+.0f}% time saved)" if ratio < 1 else
              f"head / base: {ratio:.2f} ({(ratio - 1) * 100:.0f}% slower)")  # fmt: skip


if __name__ == "__main__":
    main()
