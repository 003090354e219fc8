"""The mutation score: how the checks of a set of scenarios judged their generated mutants and rewrites.

A mutant is a wrong solution that must fail (killed) unless its scenario declares it equivalent with a
reason (declared); one that passes anyway survived. A rewrite is a right solution that must pass. A mutant
the app refused outright changed nothing (stillborn) and is not counted. The score is the share of counted
mutants that are killed or declared.
"""

from __future__ import annotations

from collections.abc import Iterable

from pare.bench.selftest import MutantVerdict


class MutationScore:
    """The mutants and rewrites of the scenarios checked, counted for the library."""

    def __init__(self) -> None:
        self.by_scenario: dict[str, tuple[MutantVerdict, ...]] = {}

    def add(self, scenario_id: str, verdicts: Iterable[MutantVerdict]) -> None:
        """Count ``scenario_id``'s verdicts."""
        self.by_scenario[scenario_id] = tuple(verdicts)

    def count(self, outcome: str) -> int:
        """How many mutants or rewrites got ``outcome``."""
        return sum(v.outcome == outcome for vs in self.by_scenario.values() for v in vs)

    @property
    def generated(self) -> int:
        """The mutants counted: killed, declared or survived (stillborn ones changed nothing)."""
        return self.count("killed") + self.count("declared") + self.count("survived")

    @property
    def score(self) -> float | None:
        """The share of counted mutants that are killed or declared (None when there is none)."""
        if not self.generated:
            return None
        return (self.count("killed") + self.count("declared")) / self.generated

    def summary(self) -> str:
        """The gate's summary line of the score."""
        killed, declared, survived = self.count("killed"), self.count("declared"), self.count("survived")
        passed, failed = self.count("passed"), self.count("failed")
        return (
            f"mutants: {self.generated} generated, {killed} killed, {declared} declared, "
            f"{survived} survived; rewrites: {passed} of {passed + failed} pass"
        )

    def score_line(self) -> str:
        """The mutation score in one line: the share judged as they must be, and what it is made of."""
        score = self.score
        if score is None:
            return "mutation score: no mutant generated"
        killed = self.count("killed") / self.generated
        scenarios = sum(1 for verdicts in self.by_scenario.values() if verdicts)
        return (
            f"mutation score: {score:.1%} of {self.generated} mutants killed or declared equivalent "
            f"({killed:.1%} killed) over {scenarios} scenario{'' if scenarios == 1 else 's'} with mutants"
        )

    def misjudged(self) -> list[tuple[str, MutantVerdict]]:
        """The surviving mutants and failing rewrites, scenario by scenario."""
        return [
            (scenario_id, verdict)
            for scenario_id, verdicts in self.by_scenario.items()
            for verdict in verdicts
            if verdict.outcome in ("survived", "failed")
        ]
