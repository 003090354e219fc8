"""How far the judge fallback's facts rule reaches, played over the library without a judge model.

    PYTHONPATH=$PWD/src python benchmarks/fact_reach.py [-v]

Plays the oracle and every variant of each scenario with a judge check that has ``facts`` (as the gate
does) and, for each such check, reads the texts its fallback reads with the facts rule
(:mod:`pare.scenarios.fact_details`). Reports:

- ``failing variants caught``: the ``expect: fail`` variants in which some judge check with facts finds, in
  every text it reads, a detail the allowed texts do not give, so the rule alone fails that check, whatever
  the fallback the author wrote for the variant; and the same among the variants whose ``fails`` names a
  goal with such a check (counted on that goal's checks);
- ``solution texts needing the solutions``: texts of the oracle and the passing variants that state a
  detail neither the facts nor the criterion give (allowed only because a solution writes it): each is a
  fact the author may have forgotten, which the judge model needs too (``-v`` lists them).
"""

from __future__ import annotations

import argparse
import sys
from datetime import datetime

from pare.bench.selftest import check_scenario
from pare.scenarios import load_scenarios
from pare.scenarios.checks import FallbackTexts, fallback_texts
from pare.scenarios.fact_details import AllowedDetails
from pare.scenarios.model import Scenario


def _strays(found: FallbackTexts, allowed: AllowedDetails) -> list[str]:
    """What ``allowed`` rejects in each text of ``found`` (one line per rejected text)."""
    lines = []
    for text, sent in found.texts:
        stray = allowed.stray(text, sent)
        if stray is not None:
            lines.append(f"{found.goal}: {stray[1]!r} states {stray[0].shown}")
    return lines


def _every_text_rejected(found: FallbackTexts) -> bool:
    return bool(found.texts) and all(found.allowed.stray(text, sent) for text, sent in found.texts)


def main(argv: list[str] | None = None) -> int:
    """Play the library and print the facts rule's reach."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("-v", "--verbose", action="store_true", help="list the texts counted")
    verbose = parser.parse_args(argv).verbose
    with_facts: list[Scenario] = [
        scenario
        for scenario in load_scenarios()
        if any(check.form == "judge" and check.body.facts for goal in scenario.goals for check in goal.checks)
    ]
    failing = caught = solution_texts = needing = aimed = aimed_caught = 0
    for scenario in with_facts:
        verdict = check_scenario(scenario, runs={"oracle"})
        start: datetime = scenario.start
        for run, result in verdict.details.items():
            found = fallback_texts(scenario, result.env.log.entries, result.env.snapshot(shared=True))
            expected_fail = run.startswith("variant:") and any(
                variant.expect == "fail" and f"variant:{variant.id}" == run for variant in scenario.variants
            )
            if expected_fail:
                failing += 1
                if any(_every_text_rejected(check) for check in found):
                    caught += 1
                    if verbose:
                        print(f"caught {scenario.id} [{run}]")
                named = next(v.fails for v in scenario.variants if f"variant:{v.id}" == run)
                on_named = [check for check in found if check.goal in named]
                if on_named:  # the variant was written to fail a goal a judge check with facts reads
                    aimed += 1
                    aimed_caught += any(_every_text_rejected(check) for check in on_named)
                continue
            for check in found:
                strict = AllowedDetails.of(
                    check.check.facts, start, lambda check=check: (check.check.criterion,)
                )
                solution_texts += len(check.texts)
                lines = _strays(check, strict)
                needing += len(lines)
                if verbose:
                    for line in lines:
                        print(f"needs a solution: {scenario.id} [{run}] {line}")
    print(f"scenarios with judge facts: {len(with_facts)}")
    print(f"failing variants caught by the facts rule alone: {caught} of {failing}")
    print(
        "failing variants that name a goal with a judge check with facts, caught there by the facts rule "
        f"alone: {aimed_caught} of {aimed}"
    )
    print(f"solution texts stating a detail only a solution gives: {needing} of {solution_texts}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
