"""How far the invented-details rule reaches: the runs it alone decides, played as the gate plays them.

    PYTHONPATH=$PWD/src python benchmarks/invented_reach.py [--mutants] [-v] [--prefix y4_] [paths...]

Plays the self-test gate's runs of each scenario (the library by default, else the files or folders
given) and reads each verdict with and without the invented details (:mod:`pare.scenarios.invented`).
Reports:

- ``solutions with invented details``: runs of the oracle, the fixed runs that must pass and the passing
  variants in which the rule finds a detail (by construction none: each must be 0);
- ``failing variants rejected by it alone``: ``expect: fail`` variants whose goals and side effects pass
  and that only an invented detail fails; and ``also by it``: those in which it finds a detail at all;
- with ``--mutants``, ``mutants rejected by it alone``: killed mutants whose first reason is an invented
  detail (the gate names check failures and side effects first, so none of those fail them);
- ``misjudged variants``: variants whose verdict differs from the one they declare, without the rule
  (before) and with it (after); ``--prefix`` counts only the variants whose id starts with it too.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from pare.bench.selftest import check_scenario
from pare.scenarios import load_scenarios
from pare.scenarios.checks import Outcome
from pare.scenarios.loader import load_scenario


def _without_invented(outcome: Outcome) -> bool:
    """The verdict as it was before invented details: goals and side effects."""
    return all(goal.passed for goal in outcome.goals) and not outcome.side_effects


def main(argv: list[str] | None = None) -> int:
    """Play the scenarios and print the rule's reach."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "paths", nargs="*", type=Path, help="scenario files or folders (default: the library)"
    )
    parser.add_argument("--mutants", action="store_true", help="also play the generated mutants")
    parser.add_argument(
        "--prefix", action="append", default=[], help="also count variants with this id prefix"
    )
    parser.add_argument("-v", "--verbose", action="store_true", help="name every run counted")
    options = parser.parse_args(argv)
    files = [
        file for path in options.paths for file in (sorted(path.glob("*.yaml")) if path.is_dir() else [path])
    ]
    scenarios = [load_scenario(file) for file in files] if files else load_scenarios()
    solutions = solutions_flagged = failing = failing_alone = failing_also = mutants = mutants_alone = 0
    misjudged = {"all": [0, 0, 0], **{prefix: [0, 0, 0] for prefix in options.prefix}}  # runs, before, after
    for scenario in scenarios:
        verdict = check_scenario(scenario, mutants=options.mutants)
        expects = {f"variant:{variant.id}": variant.expect == "pass" for variant in scenario.variants}
        for run in verdict.runs:
            result = verdict.details.get(run.run)
            if result is None or run.success is None:
                continue
            before = _without_invented(result.outcome)
            if run.expected_success:
                solutions += 1
                if result.outcome.invented:
                    solutions_flagged += 1
                    print(
                        f"SOLUTION FLAGGED {scenario.id} [{run.run}]: {result.outcome.invented[0].describe()}"
                    )
            elif run.run in expects:
                failing += 1
                failing_also += bool(result.outcome.invented)
                if before and result.outcome.invented:
                    failing_alone += 1
                    if options.verbose:
                        print(f"alone {scenario.id} [{run.run}]: {result.outcome.invented[0].describe()}")
            if run.run in expects:
                variant = run.run.removeprefix("variant:")
                for prefix, counts in misjudged.items():
                    if prefix == "all" or variant.startswith(prefix):
                        counts[0] += 1
                        counts[1] += before != run.expected_success
                        counts[2] += run.success != run.expected_success
                        if options.verbose and prefix != "all" and run.success != run.expected_success:
                            print(f"misjudged {scenario.id} [{run.run}]: must {run.expected_success}")
        for mutant in verdict.mutants:
            if mutant.expect != "fail":
                continue
            mutants += 1
            if mutant.outcome == "killed" and mutant.detail.startswith("invented:"):
                mutants_alone += 1
                if options.verbose:
                    print(f"mutant {scenario.id} [{mutant.name}]: {mutant.detail}")
    print(f"scenarios: {len(scenarios)}")
    print(f"solutions with invented details: {solutions_flagged} of {solutions}")
    print(f"failing variants rejected by invented details alone: {failing_alone} of {failing}")
    print(f"failing variants in which it finds an invented detail (also failed otherwise): {failing_also}")
    if options.mutants:
        print(f"mutants rejected by invented details alone: {mutants_alone} of {mutants}")
    for prefix, (runs, before, after) in misjudged.items():
        label = "variants" if prefix == "all" else f"variants {prefix}*"
        print(f"misjudged {label}: {before} of {runs} before, {after} after")
    return 0


if __name__ == "__main__":
    sys.exit(main())
