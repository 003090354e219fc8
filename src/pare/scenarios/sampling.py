"""Stratified samples of the library: a smaller split that keeps the library's mix.

The paper's user-model ablation runs a subset of the benchmark; for its results to speak for the whole
library, the subset must use the apps, test the capabilities and span the difficulties in the library's
proportions. :func:`stratified_sample` draws such a subset by balanced sampling: scenarios are taken one
at a time, each time the one that brings the sample's profile (the share of scenarios using each app,
having each tag, of each difficulty and of each kind, and of each app mix: the number of apps a scenario
uses) closest to the library's. Ties are broken by a seeded shuffle, so a seed always gives the same
sample.
"""

from __future__ import annotations

import random
from collections import Counter
from collections.abc import Iterable, Sequence
from dataclasses import dataclass

from pare.scenarios.model import Scenario


def features(scenario: Scenario) -> list[str]:
    """What the sample must keep in proportion: apps, tags, difficulty, kind and app-mix size."""
    mix = min(len(scenario.apps), 4)
    return [
        *(f"app:{app}" for app in sorted(set(scenario.apps))),
        *(f"tag:{tag}" for tag in sorted(set(scenario.tags))),
        f"difficulty:{scenario.difficulty}",
        f"kind:{scenario.kind}",
        f"apps used:{mix}{'+' if mix == 4 else ''}",
    ]


def profile(scenarios: Iterable[Scenario]) -> dict[str, float]:
    """The share of ``scenarios`` having each feature."""
    chosen = list(scenarios)
    counts = Counter(feature for scenario in chosen for feature in features(scenario))
    return {feature: count / len(chosen) for feature, count in counts.items()} if chosen else {}


@dataclass(frozen=True, slots=True)
class Sample:
    """A stratified sample and how far its profile is from the library's."""

    ids: tuple[str, ...]
    library: dict[str, float]
    sample: dict[str, float]

    @property
    def largest_gap(self) -> tuple[str, float]:
        """The feature whose share differs most between the sample and the library, and by how much."""
        gaps = {name: abs(self.sample.get(name, 0.0) - share) for name, share in self.library.items()}
        name = max(gaps, key=lambda key: (gaps[key], key))
        return name, gaps[name]


def stratified_sample(scenarios: Sequence[Scenario], size: int, seed: int = 0) -> Sample:
    """``size`` scenarios whose profile is as close to ``scenarios``' as balanced sampling gets."""
    if not 0 < size <= len(scenarios):
        raise ValueError(f"a sample of {size} from {len(scenarios)} scenarios is not possible")
    target = profile(scenarios)
    pool = sorted(scenarios, key=lambda s: s.id)
    random.Random(seed).shuffle(pool)
    counts: Counter[str] = Counter()
    chosen: list[Scenario] = []
    for taken in range(1, size + 1):
        best, best_cost = 0, float("inf")
        for index, candidate in enumerate(pool):
            added = Counter(features(candidate))
            cost = sum(((counts[name] + added[name]) / taken - share) ** 2 for name, share in target.items())
            if cost < best_cost:  # strictly better: the seeded order decides among equals
                best, best_cost = index, cost
        pick = pool.pop(best)
        chosen.append(pick)
        counts.update(features(pick))
    return Sample(tuple(sorted(s.id for s in chosen)), target, profile(chosen))
