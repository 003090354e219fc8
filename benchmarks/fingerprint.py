"""Fingerprints of what the library's episodes produce, so a speed change can show it changed no outcome.

    python benchmarks/fingerprint.py --out /tmp/fp-base      # on the base checkout
    python benchmarks/fingerprint.py --out /tmp/fp-head      # on the changed one
    diff -r /tmp/fp-base /tmp/fp-head                        # nothing: same trajectories, byte for byte

Plays every library scenario in three configurations and prints one SHA-256 digest per configuration:

- ``oracle``: ``pare run --split full --runs 2`` (the oracle plays both roles), records and trajectories;
- ``faults``: the same with tool failures (0.2) and noise notifications (0.5 per minute), one run;
- ``llm``: model-backed actors (prompts rendered, text actions parsed) whose models answer what the oracle
  would do, one run: the path a real model takes, without the model.

Each episode's record (without its wall time) and trajectory go to ``--out`` as one file, so two
fingerprints that differ can be compared file by file. Prints digests only; no assertion.
"""

from __future__ import annotations

import argparse
import asyncio
import contextlib
import hashlib
import io
import json
import shutil
import sys
import tempfile
from pathlib import Path

from pare.bench.episode import arun_episode
from pare.cli import main as pare_main
from pare.scenarios import load_scenarios

sys.path.insert(0, str(Path(__file__).parent))
from episode import Bridge, ShimAssistant, ShimUser  # a sibling script

RUN_CONFIGURATIONS = {
    "oracle": ["--runs", "2"],
    "faults": ["--runs", "1", "--tool-failure-prob", "0.2", "--noise-rate", "0.5"],
}


def run_files(name: str, flags: list[str], scratch: Path) -> dict[str, str]:
    """One file's text per episode of a ``pare run`` with ``flags``: its record and its trajectory."""
    folder = scratch / name
    with contextlib.redirect_stdout(io.StringIO()):  # the run's summary is not a fingerprint
        code = pare_main(["run", "--split", "full", "--no-progress", "-o", str(folder), *flags])
    if code != 0:
        raise SystemExit(f"pare run ({name}) exited with {code}")
    files = {}
    for line in (folder / "episodes.jsonl").read_text(encoding="utf-8").splitlines():
        record = json.loads(line)
        record.pop("wall_s", None)  # the one field that is measured, not simulated
        trajectory = (
            (folder / record["trajectory"]).read_text(encoding="utf-8") if record["trajectory"] else ""
        )
        key = f"{record['scenario_id']}.run-{record['run']}"
        files[key] = json.dumps(record, sort_keys=True, ensure_ascii=False) + "\n" + trajectory + "\n"
    return files


def llm_files() -> dict[str, str]:
    """One file's text per scenario played by model-backed actors that follow the oracle."""

    async def play_all() -> dict[str, str]:
        files = {}
        for scenario in load_scenarios():
            bridge = Bridge(scenario)
            result = await arun_episode(scenario, ShimUser(bridge, False), ShimAssistant(bridge, False))
            files[scenario.id] = json.dumps(result.to_dict(), sort_keys=True, ensure_ascii=False) + "\n"
        return files

    return asyncio.run(play_all())


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, help="Write each episode's file under this folder (replaced).")
    options = parser.parse_args()
    with tempfile.TemporaryDirectory(prefix="pare-fingerprint-") as scratch:
        configurations = {
            name: run_files(name, flags, Path(scratch)) for name, flags in RUN_CONFIGURATIONS.items()
        }
    configurations["llm"] = llm_files()
    if options.out is not None:
        shutil.rmtree(options.out, ignore_errors=True)
    for name, files in configurations.items():
        digest = hashlib.sha256()
        for key in sorted(files):
            digest.update(key.encode() + b"\0" + files[key].encode() + b"\0")
            if options.out is not None:
                path = options.out / name / f"{key}.txt"
                path.parent.mkdir(parents=True, exist_ok=True)
                path.write_text(files[key], encoding="utf-8")
        print(f"{name:7s} {len(files):4d} episodes  sha256 {digest.hexdigest()}")


if __name__ == "__main__":
    main()
