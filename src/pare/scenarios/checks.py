"""Evaluating a scenario's goals on the action log and the final state.

A goal is met when all its checks hold; the scenario succeeds when every goal is met. Each check's
result carries a sentence saying what was looked for and what was found, so a failing run explains
itself.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import asdict, dataclass
from typing import Any

from pare.scenarios.matchers import compile_matcher
from pare.scenarios.model import ActionCheck, Check, Count, JudgeCheck, Scenario, StateCheck, as_count
from pare.scenarios.patterns import CompiledPattern
from pare.sim.log import LogEntry

Judge = Callable[[str, str], bool]
"""A model-judged condition: ``judge(criterion, text)`` says whether ``text`` meets ``criterion``."""

_AT_LEAST_ONE = Count(min=1)


@dataclass(frozen=True, slots=True)
class CheckResult:
    """The verdict on one check and why."""

    goal: str
    index: int
    form: str
    passed: bool
    detail: str
    description: str = ""


@dataclass(frozen=True, slots=True)
class GoalResult:
    """Whether one goal was met, with its checks' verdicts."""

    id: str
    description: str
    passed: bool
    checks: tuple[CheckResult, ...]


@dataclass(frozen=True, slots=True)
class Outcome:
    """The verdict on a whole episode: success, and per-goal results (the paper's R_Succeed)."""

    success: bool
    goals: tuple[GoalResult, ...]

    @property
    def goal_rate(self) -> float:
        """Share of goals met."""
        return sum(goal.passed for goal in self.goals) / len(self.goals) if self.goals else 0.0

    def failures(self) -> list[CheckResult]:
        """Every failing check."""
        return [check for goal in self.goals for check in goal.checks if not check.passed]

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready form."""
        return {
            "success": self.success,
            "goal_rate": self.goal_rate,
            "goals": [asdict(goal) for goal in self.goals],
        }


def evaluate(
    scenario: Scenario,
    log: Sequence[LogEntry],
    state: Mapping[str, Any],
    *,
    judge: Judge | None = None,
) -> Outcome:
    """Evaluate every goal of ``scenario`` on ``log`` and the final ``state`` snapshot.

    Judge checks use ``judge`` when given, else their deterministic fallback.
    """
    goals = []
    for goal in scenario.goals:
        results = tuple(
            _evaluate_check(goal.id, index, check, scenario, log, state, judge)
            for index, check in enumerate(goal.checks)
        )
        goals.append(GoalResult(goal.id, goal.description, all(r.passed for r in results), results))
    return Outcome(success=all(goal.passed for goal in goals), goals=tuple(goals))


def _evaluate_check(
    goal: str,
    index: int,
    check: Check,
    scenario: Scenario,
    log: Sequence[LogEntry],
    state: Mapping[str, Any],
    judge: Judge | None,
) -> CheckResult:
    if check.action is not None:
        passed, detail = _action(check.action, scenario, log)
    elif check.no_action is not None:
        pattern = CompiledPattern.of(check.no_action, scenario.start)
        found = pattern.find(log)
        passed = not found
        what = pattern.describe()
        detail = f"no {what}" if passed else f"forbidden {what} happened: {_calls(found)}"
    elif check.state is not None:
        passed, detail = _state(check.state, scenario, state)
    else:
        assert check.judge is not None
        passed, detail = _judge(check.judge, scenario, log, judge)
    return CheckResult(goal, index, check.form, passed, detail, check.description)


def _action(check: ActionCheck, scenario: Scenario, log: Sequence[LogEntry]) -> tuple[bool, str]:
    pattern = CompiledPattern.of(check, scenario.start)
    count = as_count(check.count, _AT_LEAST_ONE)
    found = pattern.find(log)
    wanted = f"{count.describe()} {pattern.describe()}"
    if count.allows(len(found)):
        return True, f"{wanted}: found {len(found)}"
    near = [entry for entry in log if pattern.matches_call(entry) and entry not in found]
    detail = f"wanted {wanted}; found {len(found)}"
    if near:
        detail += f"; other calls to that tool: {_calls(near)}"
    return False, detail


def _calls(entries: Sequence[LogEntry], limit: int = 3) -> str:
    shown = [f"#{e.index} {e.actor} {e.app}__{e.tool}({_short(e.args)})" for e in entries[:limit]]
    more = f" and {len(entries) - limit} more" if len(entries) > limit else ""
    return "; ".join(shown) + more


def _short(args: Mapping[str, Any], width: int = 60) -> str:
    parts = []
    for key, value in args.items():
        text = repr(value)
        parts.append(f"{key}={text if len(text) <= width else text[: width - 3] + '...'}")
    return ", ".join(parts)


class _Missing:
    def __repr__(self) -> str:
        return "<missing>"


MISSING = _Missing()


def lookup(data: Any, path: str) -> Any:
    """The value at a dotted ``path`` (mapping keys, list indexes) of JSON-like data, or :data:`MISSING`."""
    value: Any = data
    for part in path.split("."):
        if isinstance(value, Mapping) and part in value:
            value = value[part]
        elif isinstance(value, list) and part.isdigit() and int(part) < len(value):
            value = value[int(part)]
        else:
            return MISSING
    return value


def _state(check: StateCheck, scenario: Scenario, state: Mapping[str, Any]) -> tuple[bool, str]:
    value = lookup(state, check.path)
    if value is MISSING:
        return False, f"{check.path} does not exist in the final state"
    if "value" in check.model_fields_set:
        matcher = compile_matcher(check.value)
        passed = matcher.test(value, scenario.start)
        shown = _short({"value": value}, 120)
        return (
            passed,
            f"{check.path} {'matches' if passed else 'does not match'} {matcher.describe()} ({shown})",
        )
    items = list(value.values()) if isinstance(value, Mapping) else value if isinstance(value, list) else None
    if items is None:
        return (
            False,
            f"{check.path} is not a collection (it is {type(value).__name__}); use 'value' to match it",
        )
    where = tuple((name, compile_matcher(raw)) for name, raw in check.where.items())
    matching = [
        item
        for item in items
        if all(
            matcher.test(item.get(name) if isinstance(item, Mapping) else None, scenario.start)
            for name, matcher in where
        )
    ]
    count = as_count(check.count, _AT_LEAST_ONE)
    condition = "{" + ", ".join(f"{name}: {m.describe()}" for name, m in where) + "}" if where else "(any)"
    passed = count.allows(len(matching))
    return (
        passed,
        f"{check.path}: {len(matching)} of {len(items)} items match {condition}; wanted {count.describe()}",
    )


def _judge(
    check: JudgeCheck, scenario: Scenario, log: Sequence[LogEntry], judge: Judge | None
) -> tuple[bool, str]:
    pattern = CompiledPattern.of(check.action, scenario.start)
    texts = [entry.args.get(check.field) for entry in pattern.find(log)]
    candidates = [text for text in texts if isinstance(text, str)]
    if not candidates:
        return False, f"no {pattern.describe()} with a text in '{check.field}' to judge"
    if judge is not None:
        passed = any(judge(check.criterion, text) for text in candidates)
        return (
            passed,
            f"judge {'accepted' if passed else 'rejected'} {len(candidates)} text(s) for: {check.criterion}",
        )
    fallback = compile_matcher(check.fallback)
    passed = any(fallback.test(text, scenario.start) for text in candidates)
    verdict = "holds" if passed else "fails"
    return passed, f"no judge model; fallback {fallback.describe()} {verdict} on {len(candidates)} text(s)"
