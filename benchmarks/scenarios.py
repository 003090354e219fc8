"""Scenario library timings: loading and validating every file, and the self-test gate per scenario.

    python benchmarks/scenarios.py [--repeat 5] [--mutants] [PATHS ...]

With ``--mutants`` the gate also plays every scenario's generated mutants and rewrites, as ``pare scenarios
check --mutants`` does, and the line says how many it played.

The oracle runs and the gate use the cyclic collector as ``pare run`` and ``pare scenarios check`` do
(:mod:`pare.bench.collector`). Prints numbers only; no assertion. Times are the median of ``--repeat``
repetitions.
"""

from __future__ import annotations

import argparse
import statistics
import time

from pare.bench import run_episode
from pare.bench.collector import long_lived_frozen, settle
from pare.bench.selftest import check_scenario
from pare.scenarios import OracleAssistant, OracleUser, load_scenarios


def median_seconds(action: object, repeat: int) -> float:
    assert callable(action)
    samples = []
    for _ in range(repeat):
        began = time.perf_counter()
        action()
        samples.append(time.perf_counter() - began)
    return statistics.median(samples)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("paths", nargs="*", help="scenario files or directories (default: the library)")
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--mutants", action="store_true", help="the gate plays mutants and rewrites too")
    options = parser.parse_args()
    paths = options.paths or None

    load_time = median_seconds(lambda: load_scenarios(paths), options.repeat)
    scenarios = load_scenarios(paths)
    count = len(scenarios)
    print(f"scenarios: {count}")
    each = load_time / count * 1000
    print(f"load and validate the library: {load_time * 1000:.1f} ms ({each:.2f} ms per file)")

    def oracle_runs() -> None:
        for scenario in scenarios:
            result = run_episode(scenario, OracleUser(scenario), OracleAssistant(scenario))
            assert result.success, scenario.id

    with long_lived_frozen():  # as `pare run` does (pare.bench.collector)
        oracle_time = median_seconds(oracle_runs, options.repeat)
    each = oracle_time / count * 1000
    print(f"oracle run of every scenario: {oracle_time * 1000:.1f} ms ({each:.2f} ms per scenario)")

    per_scenario: list[tuple[float, str]] = []
    episodes: list[int] = []
    played_mutants: list[int] = []

    def gate() -> None:
        per_scenario.clear()
        episodes.clear()
        played_mutants.clear()
        for scenario in scenarios:
            verdict = check_scenario(scenario, mutants=options.mutants)
            assert verdict.ok, verdict.breaches()
            per_scenario.append((verdict.seconds, scenario.id))
            episodes.append(len(verdict.runs) + len(verdict.mutants))
            played_mutants.append(len(verdict.mutants))
            del verdict
            settle()  # as `pare scenarios check` does after each scenario

    with long_lived_frozen():
        gate_time = median_seconds(gate, options.repeat)
    each = gate_time / count * 1000
    played = sum(episodes)
    with_mutants = f", {sum(played_mutants)} of them mutants and rewrites" if options.mutants else ""
    print(
        f"self-test gate ({played} episodes{with_mutants}, {played / count:.1f} per scenario with its "
        "variants): "
        f"{gate_time * 1000:.1f} ms ({each:.2f} ms per scenario, "
        f"{gate_time / played * 1000:.2f} ms per episode)"
    )
    slowest = max(per_scenario)
    print(f"slowest scenario in the gate: {slowest[1]} ({slowest[0] * 1000:.1f} ms)")


if __name__ == "__main__":
    main()
