"""The library's coverage: what its scenarios use and test, against the targets the benchmark sets.

The targets are PARE-Bench's blueprint for the full library (at least 150 scenarios): the share of
scenarios using each app, every capability tag on at least 30 scenarios, difficulty near 30/45/25 %,
about a tenth of scenarios where the right move is not to propose, and at least a fifth of the goals that
judge free text doing it with a model judge (with a deterministic fallback).
"""

from __future__ import annotations

import math
from collections import Counter
from collections.abc import Iterator, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

from pare.scenarios.matchers import OPERATORS
from pare.scenarios.model import TAGS, Check, Goal, Scenario
from pare.scenarios.times import parse_time

LIBRARY_SIZE = 150
APP_SHARES: dict[str, tuple[float, float]] = {
    "email": (0.40, 0.60),
    "messaging": (0.25, 0.42),
    "shopping": (0.25, 0.42),
    "calendar": (0.20, 0.35),
    "reminder": (0.20, 0.35),
    "cab": (0.14, 0.25),
    "notes": (0.14, 0.25),
    "apartment": (0.14, 0.25),
    "contacts": (0.14, 0.25),
}
"""Share of scenarios using each app: BENCHMARK.md's "about a half / a third / a quarter / a sixth to a
fifth", as a band."""
TAG_MINIMUM = 30
DIFFICULTY_SHARES: dict[str, tuple[float, float]] = {
    "easy": (0.22, 0.38),
    "medium": (0.37, 0.53),
    "hard": (0.17, 0.33),
}
NO_PROPOSAL_SHARE = (0.07, 0.15)
JUDGE_SHARE_MINIMUM = 0.2
FREE_TEXT_FIELDS = frozenset(
    {"content", "body", "text", "message", "subject", "title", "description", "note"}
)
"""Fields that carry what someone wrote: a check reading one of them judges free text."""


def reads_free_text(check: Check) -> bool:
    """Whether ``check`` judges free text: a judge check, or a text operator on a free-text field."""
    if check.judge is not None:
        return True
    if check.action is not None:
        fields: Mapping[str, Any] = check.action.args
    elif check.state is not None:
        fields = check.state.where
    else:
        return False  # a forbidden action is not text that was read
    return any(name in FREE_TEXT_FIELDS and _reads_text(raw) for name, raw in fields.items())


def _reads_text(raw: Any) -> bool:
    if not isinstance(raw, Mapping):
        return False
    for key, value in raw.items():
        operator = OPERATORS.get(key)
        if operator is None:
            return False
        if operator.reads == "text":
            return True
        if operator.nested is not None and any(_reads_text(item) for item in operator.nested(value)):
            return True
    return False


def text_goals(scenario: Scenario) -> list[tuple[Goal, bool]]:
    """The goals that judge free text, each with whether a model judge does it."""
    return [
        (goal, any(check.judge is not None for check in goal.checks))
        for goal in scenario.goals
        if any(reads_free_text(check) for check in goal.checks)
    ]


def proposes(scenario: Scenario) -> bool:
    """Whether the right move in ``scenario`` is to propose (its oracle has interventions)."""
    return bool(scenario.oracle.interventions)


@dataclass(frozen=True, slots=True)
class Coverage:
    """The library's counts, and the gaps against the targets."""

    scenarios: int
    apps: dict[str, int]
    tags: dict[str, int]
    difficulties: dict[str, int]
    proposal: int
    no_proposal: int
    apps_per_scenario: float
    apps_per_scenario_counts: dict[int, int]
    text_goals: int
    judged_text_goals: int
    variants_passing: int
    variants_failing: int
    story_days: dict[int, int] = field(default_factory=dict)
    """Scenarios by the calendar days their story spans: from the start to the last timed event."""

    @property
    def judge_share(self) -> float:
        """Share of the goals judging free text that use a model judge."""
        return self.judged_text_goals / self.text_goals if self.text_goals else 0.0

    def share(self, count: int) -> float:
        """``count`` as a share of the scenarios."""
        return count / self.scenarios if self.scenarios else 0.0

    def gaps(self) -> list[str]:
        """Every target the library misses, with what would close it."""
        gaps = []
        if self.scenarios < LIBRARY_SIZE:
            missing = LIBRARY_SIZE - self.scenarios
            gaps.append(f"library: {self.scenarios} scenarios, {missing} short of {LIBRARY_SIZE}")
        for app, band in APP_SHARES.items():
            gaps.extend(_band_gap(f"app {app}", self.apps.get(app, 0), self.scenarios, band))
        for tag in TAGS:
            count = self.tags.get(tag, 0)
            if count < TAG_MINIMUM:
                gaps.append(f"tag {tag}: on {count} scenarios, {TAG_MINIMUM - count} short of {TAG_MINIMUM}")
        for difficulty, band in DIFFICULTY_SHARES.items():
            gaps.extend(
                _band_gap(
                    f"difficulty {difficulty}", self.difficulties.get(difficulty, 0), self.scenarios, band
                )
            )
        gaps.extend(_band_gap("no-proposal scenarios", self.no_proposal, self.scenarios, NO_PROPOSAL_SHARE))
        if self.judge_share < JUDGE_SHARE_MINIMUM:
            needed = _needed(self.judged_text_goals, self.text_goals, JUDGE_SHARE_MINIMUM)
            gaps.append(
                f"judge checks: {self.judged_text_goals} of {self.text_goals} text goals "
                f"({self.judge_share:.0%}); {needed} more to reach {JUDGE_SHARE_MINIMUM:.0%}"
            )
        return gaps


def _needed(have: int, total: int, share: float) -> int:
    needed = 0
    while total and (have + needed) / total < share:
        needed += 1
    return needed


def _band_gap(label: str, count: int, total: int, band: tuple[float, float]) -> Iterator[str]:
    if not total:
        return
    share = count / total
    low, high = band
    if low <= share <= high:
        return
    side = "below" if share < low else "above"
    size = max(total, LIBRARY_SIZE)
    yield (
        f"{label}: {count} of {total} ({share:.0%}), {side} the {low:.0%}-{high:.0%} target "
        f"({math.ceil(low * size)}-{math.floor(high * size)} of {size} scenarios)"
    )


def coverage(scenarios: Sequence[Scenario]) -> Coverage:
    """The coverage of ``scenarios``."""
    apps: Counter[str] = Counter()
    tags: Counter[str] = Counter()
    difficulties: Counter[str] = Counter()
    sizes: Counter[int] = Counter()
    texts = judged = passing = failing = 0
    for scenario in scenarios:
        used = scenario.all_apps
        apps.update(used)
        sizes[len(used)] += 1
        tags.update(scenario.tags)
        difficulties[scenario.difficulty] += 1
        goals = text_goals(scenario)
        texts += len(goals)
        judged += sum(by_judge for _, by_judge in goals)
        passing += sum(variant.expect == "pass" for variant in scenario.variants)
        failing += sum(variant.expect == "fail" for variant in scenario.variants)
    proposal = sum(proposes(scenario) for scenario in scenarios)
    return Coverage(
        scenarios=len(scenarios),
        apps=dict(apps.most_common()),
        tags={tag: tags.get(tag, 0) for tag in TAGS},
        difficulties={name: difficulties.get(name, 0) for name in ("easy", "medium", "hard")},
        proposal=proposal,
        no_proposal=len(scenarios) - proposal,
        apps_per_scenario=sum(size * count for size, count in sizes.items()) / len(scenarios)
        if scenarios
        else 0.0,
        apps_per_scenario_counts=dict(sorted(sizes.items())),
        text_goals=texts,
        judged_text_goals=judged,
        variants_passing=passing,
        variants_failing=failing,
        story_days=dict(sorted(Counter(story_days(scenario) for scenario in scenarios).items())),
    )


def story_days(scenario: Scenario) -> int:
    """The calendar days a scenario's story spans: from its start to its last event at a set time (events
    that react to actions follow them, within the same stretch).
    """
    times = [parse_time(event.at, scenario.start) for event in scenario.events if event.at is not None]
    return (max(times).date() - scenario.start.date()).days + 1 if times else 1


def format_coverage(report: Coverage) -> list[str]:
    """The coverage as lines of text."""
    total = report.scenarios
    lines = [f"scenarios: {total}"]

    def row(label: str, counts: Mapping[Any, int]) -> None:
        parts = [f"{name} {count} ({report.share(count):.0%})" for name, count in counts.items()]
        lines.append(f"{label}: " + ", ".join(parts))

    row("apps (share of scenarios using each)", report.apps)
    row("tags", report.tags)
    row("difficulty", report.difficulties)
    row("kind", {"proposal": report.proposal, "no_proposal": report.no_proposal})
    sizes = ", ".join(f"{size} apps: {count}" for size, count in report.apps_per_scenario_counts.items())
    lines.append(f"apps per scenario: {report.apps_per_scenario:.1f} on average ({sizes})")
    lines.append(
        f"text goals: {report.text_goals}, of which judged by a model: {report.judged_text_goals} "
        f"({report.judge_share:.0%})"
    )
    lines.append(f"variants: {report.variants_passing} passing, {report.variants_failing} failing")
    days = ", ".join(
        f"{span} day{'s' if span > 1 else ''}: {count}" for span, count in report.story_days.items()
    )
    several = sum(count for span, count in report.story_days.items() if span > 1)
    lines.append(f"story span (start to the last timed event): {days}; over several days: {several}")
    gaps = report.gaps()
    lines.append(f"gaps against the targets: {len(gaps)}" if gaps else "gaps against the targets: none")
    lines.extend(f"  - {gap}" for gap in gaps)
    return lines
