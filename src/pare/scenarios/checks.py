"""Evaluating a scenario's goals on the action log and the final state.

A goal is met when all its checks hold; the scenario succeeds when every goal is met. Each check's
result carries a sentence saying what was looked for and what was found, so a failing run explains
itself.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, fields, replace
from datetime import datetime
from typing import Any

from pare.env.attribution import Attribution, item_key, place_of
from pare.scenarios.matchers import compile_matcher
from pare.scenarios.model import (
    WHERE_ANY,
    WHERE_KEY,
    ActionCheck,
    ActionPattern,
    Check,
    Count,
    JudgeCheck,
    Scenario,
    StateCheck,
    as_count,
)
from pare.scenarios.patterns import CompiledPattern
from pare.sim.log import Actor, LogEntry

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
    user_made: bool = False
    """The check failed, but would hold had the user's own work been the assistant's: the user did it."""

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready form: every field, in declaration order (the values are immutable: no copies)."""
        return {name: getattr(self, name) for name in _CHECK_FIELDS}


_CHECK_FIELDS = tuple(field.name for field in fields(CheckResult))


@dataclass(frozen=True, slots=True)
class GoalResult:
    """Whether one goal was met, with its checks' verdicts."""

    id: str
    description: str
    passed: bool
    checks: tuple[CheckResult, ...]

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready form (what ``dataclasses.asdict`` gives, without its deep copies of every string)."""
        return {
            "id": self.id,
            "description": self.description,
            "passed": self.passed,
            "checks": [check.to_dict() for check in self.checks],
        }


@dataclass(frozen=True, slots=True)
class Outcome:
    """The verdict on a whole episode: success, and per-goal results (the paper's R_Succeed)."""

    success: bool
    goals: tuple[GoalResult, ...]
    user_did_work: bool = False
    """The episode failed and some of what the assistant was meant to make was made by the user instead
    (a check on the assistant's work would hold had the user's work counted): a failure of the assistant,
    counted apart in the metrics."""

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
            "user_did_work": self.user_did_work,
            "goals": [goal.to_dict() for goal in self.goals],
        }


@dataclass(frozen=True, slots=True)
class _Context:
    scenario: Scenario
    log: Sequence[LogEntry]
    state: Mapping[str, Any]
    attribution: Attribution
    credit_user: bool = False
    """Count the user's own work as the assistant's (to tell whether the user did the task by hand)."""

    def makers(self, actor: Actor) -> frozenset[Actor]:
        if self.credit_user and actor == "assistant":
            return frozenset({"assistant", "user"})
        return frozenset({actor})

    def pattern(self, pattern: ActionPattern) -> CompiledPattern:
        if self.credit_user and pattern.actor == "assistant":
            pattern = pattern.model_copy(update={"actor": "any"})
        return CompiledPattern.of(pattern, self.scenario.start)


def evaluate(
    scenario: Scenario,
    log: Sequence[LogEntry],
    state: Mapping[str, Any],
    *,
    judge: Judge | None = None,
    attribution: Attribution | None = None,
) -> Outcome:
    """Evaluate every goal of ``scenario`` on ``log`` and the final ``state`` snapshot.

    Judge checks use ``judge`` when given, else their deterministic fallback. ``attribution`` (the
    environment's) says who made each item, for state checks with ``by``; without it nothing counts as
    anyone's work. A failing check on the assistant's work is evaluated again with the user's work
    credited to the assistant, to tell whether the user did it by hand (:attr:`CheckResult.user_made`).
    """
    context = _Context(scenario, log, state, attribution or Attribution())
    credited = _Context(scenario, log, state, context.attribution, credit_user=True)
    goals = []
    for goal in scenario.goals:
        results = []
        for index, check in enumerate(goal.checks):
            result = _evaluate_check(goal.id, index, check, context, judge)
            if not result.passed and _on_the_assistant(check):
                again = _evaluate_check(goal.id, index, check, credited, None)
                result = replace(result, user_made=again.passed)
            results.append(result)
        goals.append(GoalResult(goal.id, goal.description, all(r.passed for r in results), tuple(results)))
    success = all(goal.passed for goal in goals)
    user_did_work = not success and any(check.user_made for goal in goals for check in goal.checks)
    return Outcome(success=success, goals=tuple(goals), user_did_work=user_did_work)


def _on_the_assistant(check: Check) -> bool:
    """Whether ``check`` is about who did the work (a judge check reads the text, not who wrote it)."""
    if check.action is not None:
        return check.action.actor == "assistant"
    return check.state is not None and check.state.by == "assistant"


def _evaluate_check(
    goal: str, index: int, check: Check, context: _Context, judge: Judge | None
) -> CheckResult:
    if check.action is not None:
        passed, detail = _action(check.action, context)
    elif check.no_action is not None:
        pattern = CompiledPattern.of(check.no_action, context.scenario.start)
        found = pattern.find(context.log)
        passed = not found
        what = pattern.describe()
        detail = f"no {what}" if passed else f"forbidden {what} happened: {_calls(found)}"
    elif check.state is not None:
        passed, detail = _state(check.state, context)
    else:
        assert check.judge is not None
        passed, detail = _judge(check.judge, context, judge)
    return CheckResult(goal, index, check.form, passed, detail, check.description)


def _action(check: ActionCheck, context: _Context) -> tuple[bool, str]:
    log = context.log
    pattern = context.pattern(check)
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


class _ItemCondition:
    """A state check's ``where``: every field's matcher holds, and of an ``any_of`` list one mapping does."""

    def __init__(self, where: Mapping[str, Any]) -> None:
        self.fields = tuple((name, compile_matcher(raw)) for name, raw in where.items() if name != WHERE_ANY)
        self.alternatives = tuple(_ItemCondition(item) for item in where.get(WHERE_ANY, ()))

    def test(self, item: Any, start: datetime, key: str) -> bool:
        record = item if isinstance(item, Mapping) else {}
        return all(
            matcher.test(key if name == WHERE_KEY else record.get(name), start)
            for name, matcher in self.fields
        ) and (not self.alternatives or any(option.test(item, start, key) for option in self.alternatives))

    def describe(self) -> str:
        parts = [f"{name}: {matcher.describe()}" for name, matcher in self.fields]
        if self.alternatives:
            parts.append("any of " + " or ".join(option.describe() for option in self.alternatives))
        return "{" + ", ".join(parts) + "}"


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


def _state(check: StateCheck, context: _Context) -> tuple[bool, str]:
    start, state = context.scenario.start, context.state
    value = lookup(state, check.path)
    if value is MISSING:
        return False, f"{check.path} does not exist in the final state"
    makers = None if check.by is None else context.makers(check.by)
    if "value" in check.model_fields_set:
        matcher = compile_matcher(check.value)
        passed = matcher.test(value, start)
        shown = _short({"value": value}, 120)
        detail = f"{check.path} {'matches' if passed else 'does not match'} {matcher.describe()} ({shown})"
        if makers is not None:
            place = place_of(state, check.path)
            made = place is not None and context.attribution.credits(place, makers)
            detail += f"; {'made' if made else 'not made'} by the {check.by}"
            passed = passed and made
        return passed, detail
    items: list[tuple[str, Any]] | None
    if isinstance(value, Mapping):
        items = [(str(key), item) for key, item in value.items()]
    elif isinstance(value, list):
        items = [(item_key(item), item) for item in value]
    else:
        return (
            False,
            f"{check.path} is not a collection (it is {type(value).__name__}); use 'value' to match it",
        )
    where = _ItemCondition(check.where)
    matching = [(key, item) for key, item in items if where.test(item, start, key)]
    count = as_count(check.count, _AT_LEAST_ONE)
    condition = where.describe() if check.where else "(any)"
    detail = f"{check.path}: {len(matching)} of {len(items)} items match {condition}"
    if makers is not None:
        place = place_of(state, check.path) or ()
        matching = [
            (key, item) for key, item in matching if context.attribution.credits((*place, key), makers)
        ]
        detail += f", {len(matching)} of them made by the {check.by}"
    passed = count.allows(len(matching))
    return passed, f"{detail}; wanted {count.describe()}"


def _judge(check: JudgeCheck, context: _Context, judge: Judge | None) -> tuple[bool, str]:
    scenario, log = context.scenario, context.log
    pattern = context.pattern(check.action)
    texts = [entry.args.get(check.field) for entry in pattern.find(log)]
    candidates = [text for text in texts if isinstance(text, str)]
    if not candidates:
        return False, f"no {pattern.describe()} with a text in '{check.field}' to judge"
    if check.together and len(candidates) > 1:
        candidates = ["\n\n".join(candidates)]  # one answer sent in parts is judged as the whole
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
