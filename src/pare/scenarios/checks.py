"""Evaluating a scenario's goals on the action log and the final state.

A goal is met when all its checks hold; the scenario succeeds when every goal is met. Each check's
result carries a sentence saying what was looked for and what was found, so a failing run explains
itself.

Each form of check (``action``, ``no_action``, ``state``, ``judge``: its key in a scenario file) is one
:class:`CheckForm` in :data:`CHECK_FORMS`: its model, its compiled rule (a :class:`Rule`: the verdict,
what it looks for, and the log entries or state places the viewer links it to) and what the loader asks
of it. A new form is a module with its model and rule, its field on :class:`~pare.scenarios.model.Check`
and one :func:`register_check_form` call.
"""

from __future__ import annotations

import asyncio
import dataclasses
import typing
from abc import ABC, abstractmethod
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, fields, replace
from datetime import datetime
from functools import partial
from types import MappingProxyType
from typing import Any, Protocol

from pydantic import BaseModel

from pare.env.attribution import Attribution, StatePath, item_key, place_of
from pare.errors import RunFailure, UserInputError, first_error
from pare.scenarios import explain as explaining
from pare.scenarios.excerpts import quote
from pare.scenarios.fact_details import AllowedDetails, Detail, solution_texts
from pare.scenarios.file_identity import ATTACHMENT_FIELDS, FileIdentity
from pare.scenarios.invented import InventedDetail, done_values
from pare.scenarios.item_text import item_text
from pare.scenarios.matchers import compile_matcher, written_at
from pare.scenarios.model import (
    CHECK_FORM_KEYS,
    WHERE_ANY,
    WHERE_KEY,
    WHERE_TEXT,
    ActionCheck,
    ActionPattern,
    AnyOfChecks,
    Check,
    Count,
    JudgeCheck,
    Scenario,
    StateCheck,
    as_count,
)
from pare.scenarios.occurrences import DUE_FIELD, occurrence_records
from pare.scenarios.patterns import CompiledPattern
from pare.scenarios.person_details import NameFinder, known_names, owner_names
from pare.scenarios.read_moment import due_moment, fires_at
from pare.scenarios.reading import CallReader
from pare.scenarios.side_effects import Change
from pare.sim.log import Actor, LogEntry


@dataclass(frozen=True, slots=True)
class JudgeVerdict:
    """A judge's verdict on one text, and its one-sentence reason (empty when it gave none)."""

    passed: bool
    reason: str = ""
    answer: str = ""
    """The judge's answer as it gave it, which the verdict and the reason were read from."""
    model: str = ""
    """The model that answered (empty for a judge that is not a model)."""

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready form."""
        return {"passed": self.passed, "reason": self.reason, "answer": self.answer, "model": self.model}


class Judge(Protocol):
    """A model-judged condition: ``await judge(criterion, text, facts)`` says whether ``text`` meets
    ``criterion``, given what the scenario says is true (``facts``, maybe none), and why. It is awaited in
    the episode's event loop, so a model judge calls through the run's shared client.
    """

    async def __call__(self, criterion: str, text: str, facts: Sequence[str] = ()) -> JudgeVerdict:
        """The verdict on ``text``."""
        ...


Question = tuple[str, str, tuple[str, ...]]
"""What a judge is asked: a criterion, a text and the facts."""


class JudgeAnswers:
    """The judge's verdicts on the texts of one evaluation's judge checks, asked before the checks are
    evaluated (:func:`aevaluate`): evaluating is synchronous, asking a model is not.
    """

    def __init__(self, verdicts: Mapping[Question, JudgeVerdict | Exception] | None = None) -> None:
        self._verdicts = dict(verdicts or {})

    def verdict(self, criterion: str, text: str, facts: Sequence[str]) -> JudgeVerdict:
        """The verdict asked for ``text`` (a question never asked is a mistake of the caller's). A judge
        that raised on it raises again here, inside the check, which then fails saying what it raised.
        """
        try:
            found = self._verdicts[(criterion, text, tuple(facts))]
        except KeyError:
            raise LookupError(f"the judge was never asked about {text[:60]!r} for: {criterion}") from None
        if isinstance(found, Exception):
            raise found
        return found


@dataclass(frozen=True, slots=True)
class JudgedText:
    """One text a judge check gave the judge, and the judge's verdict on it."""

    entries: tuple[int, ...]
    """The log indexes of the calls the text is from (several when the check judges them together)."""
    verdict: JudgeVerdict

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready form."""
        return {"entries": list(self.entries), "verdict": self.verdict.to_dict()}


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
    judged: tuple[JudgedText, ...] = ()
    """A judge check read by a model: each text it gave the judge, in order, with the judge's whole answer
    (up to the first text accepted: the rest were not sent)."""

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready form: every field, in declaration order (the values are immutable: no copies)."""
        data = {name: getattr(self, name) for name in _CHECK_FIELDS}
        data["judged"] = [text.to_dict() for text in self.judged]
        return data


_CHECK_FIELDS = tuple(field.name for field in fields(CheckResult) if field.name != "judged")
"""The fields given as they are (``judged`` holds dataclasses, turned into dicts)."""


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
    side_effects: tuple[Change, ...] = ()
    """Changes the assistant made that no solution of the scenario makes (:mod:`pare.scenarios.side_effects`):
    any of them fails the episode, whatever its goals."""
    invented: tuple[InventedDetail, ...] = ()
    """Details the assistant wrote into the apps that nothing in its world gives
    (:mod:`pare.scenarios.invented`): any of them fails the episode, whatever its goals."""

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
            "side_effects": [change.to_dict() for change in self.side_effects],
            "invented": [detail.to_dict() for detail in self.invented],
        }

    def with_side_effects(self, side_effects: Sequence[Change]) -> Outcome:
        """The verdict with the assistant's side effects added: any of them fails it."""
        found = tuple(side_effects)
        return replace(self, success=self.success and not found, side_effects=found)

    def with_invented(self, invented: Sequence[InventedDetail]) -> Outcome:
        """The verdict with the assistant's invented details added: any of them fails it."""
        found = tuple(invented)
        return replace(self, success=self.success and not found, invented=found)


async def aevaluate(
    scenario: Scenario,
    log: Sequence[LogEntry],
    state: Mapping[str, Any],
    *,
    judge: Judge | None = None,
    attribution: Attribution | None = None,
) -> Outcome:
    """:func:`evaluate`, with the judge checks read by ``judge`` (awaited in the running event loop, so a
    model judge's calls go through the run's client and its endpoint's limit). The judge checks' texts are
    asked first, the checks side by side, each check's texts in turn (an accepted text ends its judging, as
    the check reads them); then the checks are evaluated on the answers.
    """
    answers = None if judge is None else await _ask(scenario, log, state, judge)
    return evaluate(scenario, log, state, answers=answers, attribution=attribution)


async def _ask(
    scenario: Scenario, log: Sequence[LogEntry], state: Mapping[str, Any], judge: Judge
) -> JudgeAnswers:
    """The judge's verdicts on every text the judge checks of ``scenario`` would read (one question asked
    once, however many checks ask it).
    """
    compiled = compiled_goals(scenario)
    rules = [rule for _, rules in compiled.goals for rule in rules if isinstance(rule, _JudgeRule)]
    if not rules:
        return JudgeAnswers()
    view = _StateView(state)
    context = _Context(
        scenario.start, log, view, Attribution(), None, CallReader.of_state(view.whole, compiled.files)
    )
    asked: dict[Question, asyncio.Task[JudgeVerdict | Exception]] = {}

    async def answer(question: Question) -> JudgeVerdict | Exception:
        try:
            return await judge(*question)
        except (RunFailure, UserInputError):  # a provider or a configuration: no verdict on the episode
            raise
        except Exception as error:  # the judge's own bug: the checks that asked it fail, saying so
            return error

    try:
        async with asyncio.TaskGroup() as group:  # one failing call cancels the others

            async def judged(rule: _JudgeRule) -> None:
                check = rule.judge
                for _, text in rule.texts(context).candidates:
                    question = (check.criterion, text, tuple(check.facts))
                    if question not in asked:
                        asked[question] = group.create_task(answer(question))
                    said = await asked[question]
                    if isinstance(said, Exception) or said.passed:
                        return

            for rule in rules:
                group.create_task(judged(rule))
    except BaseExceptionGroup as errors:  # the call's own error (a provider down, a cache miss), as raised
        raise first_error(errors) from None
    return JudgeAnswers({question: task.result() for question, task in asked.items()})


def evaluate(
    scenario: Scenario,
    log: Sequence[LogEntry],
    state: Mapping[str, Any],
    *,
    answers: JudgeAnswers | None = None,
    attribution: Attribution | None = None,
) -> Outcome:
    """Evaluate every goal of ``scenario`` on ``log`` and the final ``state`` snapshot.

    Judge checks read the judge's ``answers`` when given (asked beforehand: :func:`aevaluate`), else use
    their deterministic fallback. ``attribution`` (the
    environment's) says who last set each field of each item, for state checks with ``by``: an item is an
    actor's work when it wrote a value the check reads; without it nothing counts as anyone's work. A
    failing check on the assistant's work is evaluated again with the user's work credited to the
    assistant, to tell whether the user did it by hand (:attr:`CheckResult.user_made`).
    """
    view = _StateView(state)
    compiled = compiled_goals(scenario)
    reader = CallReader.of_state(view.whole, compiled.files)
    context = _Context(scenario.start, log, view, attribution or Attribution(), answers, reader)
    credited = _Context(scenario.start, log, view, context.attribution, None, reader, credit_user=True)
    goals = []
    for goal, rules in compiled.goals:
        results = []
        for index, rule in enumerate(rules):
            passed, detail = _verdict(rule, context)
            user_made = not passed and rule.on_the_assistant and _verdict(rule, credited, explain=False)[0]
            judged = _judged(rule, context)
            results.append(
                CheckResult(goal.id, index, rule.form, passed, detail, rule.description, user_made, judged)
            )
        goals.append(GoalResult(goal.id, goal.description, all(r.passed for r in results), tuple(results)))
    success = all(goal.passed for goal in goals)
    user_did_work = not success and any(check.user_made for goal in goals for check in goal.checks)
    return Outcome(success=success, goals=tuple(goals), user_did_work=user_did_work)


def goals_met(
    scenario: Scenario,
    log: Sequence[LogEntry],
    state: Mapping[str, Any] | Callable[[], Mapping[str, Any]],
    *,
    attribution: Attribution | None = None,
) -> bool:
    """Whether every goal of ``scenario`` is met: ``evaluate(...).success`` without a judge model, but
    stopping at the first check that fails and explaining nothing (for the end-when-met checks an
    episode makes on each idle turn). Checks are pure, so the cheap ones (on the action log) go first.
    ``state`` may be a function that takes the snapshot: it is called only if a state check is reached.
    """
    view = _StateView(state)
    compiled = compiled_goals(scenario)
    reader = CallReader.of_state(view.whole, compiled.files)
    context = _Context(scenario.start, log, view, attribution or Attribution(), None, reader)
    rules = compiled.cheapest_first
    return all(_verdict(rule, context, explain=False)[0] for rule in rules)


def state_check_places(
    scenario: Scenario, state: Mapping[str, Any]
) -> dict[tuple[str, int], list[StatePath]]:
    """For each state check of ``scenario`` (by goal id and position): the places of the final ``state``
    where it found what it counted (:meth:`_StateRule.places`), for pages that link a verdict to the
    calls that made them.
    """
    view = _StateView(state)
    compiled = compiled_goals(scenario)
    reader = CallReader.of_state(view.whole, compiled.files)
    return {
        (goal.id, index): places
        for goal, rules in compiled.goals
        for index, rule in enumerate(rules)
        if (places := rule.places(view, scenario.start, reader)) is not None
    }


def linked_entries(
    scenario: Scenario, log: Sequence[LogEntry], final: Mapping[str, Any] | None = None
) -> dict[tuple[str, int], list[int]]:
    """For each check that reads the action log (by goal id and position): the indexes of the entries
    that decided it (:meth:`Rule.linked`), for pages that link a verdict to its calls. The final state,
    when known, tells whom each call told and which files it carried (without it, a pattern with ``to``
    matches nothing).
    """
    compiled = compiled_goals(scenario)
    reader = None if final is None else CallReader.of_state(lambda: final, compiled.files)
    return {
        (goal.id, index): linked
        for goal, rules in compiled.goals
        for index, rule in enumerate(rules)
        if (linked := rule.linked(log, reader)) is not None
    }


def _verdict(rule: Rule, context: _Context, *, explain: bool = True) -> tuple[bool, str]:
    """``rule``'s verdict; a check that raises fails, saying what it raised, and the others still count.

    A bug in one check (a matcher meeting a value it was not written for) costs that check, not the
    episode. A model provider's failure or a run's configuration (:class:`RunFailure`,
    :class:`UserInputError`, which a judge model raises) is no verdict on the episode: it goes on up.
    """
    try:
        return rule.verdict(context, explain=explain)
    except (RunFailure, UserInputError):
        raise
    except Exception as error:  # the check's own failure: its verdict says what it was
        return False, f"{CHECK_RAISED}{type(error).__name__}: {error}"


def _judged(rule: Rule, context: _Context) -> tuple[JudgedText, ...]:
    """What the judge read for ``rule``; nothing when the judge raised (the check's verdict says so)."""
    try:
        return rule.judged(context)
    except (RunFailure, UserInputError):
        raise
    except Exception:  # already the check's failure, in its verdict
        return ()


CHECK_RAISED = "the check raised "
"""How the sentence of a check that raised begins (its exception's type and message follow)."""


class _Context:
    """What the checks of one evaluation read (a plain class: two are made for every evaluation)."""

    __slots__ = ("_done", "answers", "attribution", "credit_user", "log", "reader", "start", "state")

    def __init__(
        self,
        start: datetime,
        log: Sequence[LogEntry],
        state: _StateView,
        attribution: Attribution,
        answers: JudgeAnswers | None,
        reader: CallReader,
        *,
        credit_user: bool = False,
    ) -> None:
        self.start = start
        self.log = log
        self.state = state
        self.attribution = attribution
        self.answers = answers
        """The judge's verdicts for the judge checks (``None``: no judge model, the fallbacks decide)."""
        self.reader = reader
        """Reads the calls against the final state: whom each told, attached files by content."""
        self.credit_user = credit_user
        """Count the user's own work as the assistant's (to tell whether the user did the task by hand)."""
        self._done: AllowedDetails | None = None

    def done(self) -> AllowedDetails:
        """The details of what the assistant did (its writes' values), read once per evaluation."""
        if self._done is None:
            self._done = done_values(self.log, self.start)
        return self._done

    def makers(self, actor: Actor) -> frozenset[Actor]:
        if self.credit_user and actor == "assistant":
            return _ASSISTANT_OR_USER
        return frozenset({actor})


_ASSISTANT_OR_USER: frozenset[Actor] = frozenset({"assistant", "user"})


class _StateView:
    """The final state as the state checks read it: what is at each path is found once per evaluation,
    however many checks (and their second reading crediting the user) look there.
    """

    __slots__ = ("_items", "_places", "_source", "_state", "_values")

    def __init__(self, state: Mapping[str, Any] | Callable[[], Mapping[str, Any]]) -> None:
        self._source = state
        self._state: Mapping[str, Any] | None = None
        self._values: dict[str, Any] = {}
        self._items: dict[str, list[tuple[str, Any, Mapping[str, Any]]] | None] = {}
        self._places: dict[str, StatePath | None] = {}

    def whole(self) -> Mapping[str, Any]:
        """:attr:`state`, as a function (for a reader that takes it only if it needs it)."""
        return self.state

    @property
    def state(self) -> Mapping[str, Any]:
        """The snapshot (taken now if it was given as a function)."""
        if self._state is None:
            source = self._source
            self._state = source if isinstance(source, Mapping) else source()
        return self._state

    def value(self, path: str) -> Any:
        """What is at ``path``, or :data:`MISSING`."""
        if path not in self._values:
            self._values[path] = lookup(self.state, path)
        return self._values[path]

    def items(self, path: str) -> list[tuple[str, Any, Mapping[str, Any]]] | None:
        """The collection at ``path`` as (key, item, record) triples, or ``None`` when it is not a
        collection. The record is the item if it is a mapping, else empty: what ``where`` fields read.
        """
        if path not in self._items:
            value = self.value(path)
            items: list[tuple[str, Any]] | None = None
            if isinstance(value, Mapping):
                items = [(str(key), item) for key, item in value.items()]
            elif isinstance(value, list):
                items = [(item_key(item), item) for item in value]
            self._items[path] = None if items is None else [(key, item, _record(item)) for key, item in items]
        return self._items[path]

    def place(self, path: str) -> StatePath | None:
        """The attribution place of ``path`` (:func:`~pare.env.attribution.place_of`)."""
        if path not in self._places:
            self._places[path] = place_of(self.state, path)
        return self._places[path]


class _Pattern:
    """An action pattern compiled with its description, and again with the user's work credited to the
    assistant (``actor: any``) when it is about the assistant's work.
    """

    __slots__ = ("credited", "credited_text", "own", "own_text")

    def __init__(self, pattern: ActionPattern, start: datetime) -> None:
        self.own = CompiledPattern.of(pattern, start)
        self.own_text = self.own.describe()
        self.credited, self.credited_text = self.own, self.own_text
        if pattern.actor == "assistant":
            self.credited = CompiledPattern.of(pattern.model_copy(update={"actor": "any"}), start)
            self.credited_text = self.credited.describe()

    def of(self, context: _Context) -> tuple[CompiledPattern, str]:
        """The pattern to use in ``context``, with its description."""
        if context.credit_user:
            return self.credited, self.credited_text
        return self.own, self.own_text


class Rule(ABC):
    """One check compiled once per scenario: ``verdict`` only runs it (see :func:`compiled_goals`).

    A form's rule is made by ``rule(check, body, start)``: the check, its form's part (``check.action``
    ...) and the scenario's start.
    """

    cost = 0
    """For :func:`goals_met`: which checks to run first (cheap ones, on the action log)."""

    def __init__(self, check: Check) -> None:
        self.check = check
        self.on_the_assistant = CHECK_FORMS[check.form].about_the_assistant(check.body)
        """Whether the check is about who did the work (then it is asked again crediting the user's work
        to the assistant, to tell whether the user did it by hand)."""
        self.form = check.form
        self.description = check.description

    @abstractmethod
    def verdict(self, context: _Context, *, explain: bool = True) -> tuple[bool, str]:
        """Whether the check holds in ``context``, and what was looked for and found; with ``explain``, a
        failing check also says why its matchers refused what was found (read again only then, see
        :mod:`pare.scenarios.explain`). Callers that need only the verdict pass ``explain=False``.
        """

    @abstractmethod
    def wanted(self) -> str:
        """What the check looks for, as its verdicts say it (for a person reading the scenario)."""

    def judged(self, context: _Context) -> tuple[JudgedText, ...]:
        """The texts a judge model read for the check in ``context``, with its verdicts (none but for a
        judge check read by a model).
        """
        return ()

    def linked(self, log: Sequence[LogEntry], reader: CallReader | None) -> list[int] | None:
        """The indexes of the entries of ``log`` that decided the check, or ``None`` for a check that
        does not read the log (the viewer links such a check by :meth:`places`).
        """
        return None

    def places(self, view: _StateView, start: datetime, reader: CallReader) -> list[StatePath] | None:
        """The places of the final state where the check found what it counted, or ``None`` for a check
        that does not read the state.
        """
        return None


class _ActionRule(Rule):
    def __init__(self, check: Check, action: ActionCheck, start: datetime) -> None:
        super().__init__(check)
        self.pattern = _Pattern(action, start)
        self.count = as_count(action.count, _AT_LEAST_ONE)
        self.counted = self.count.describe()

    def wanted(self) -> str:
        return f"{self.counted} {self.pattern.own_text}"

    def verdict(self, context: _Context, *, explain: bool = True) -> tuple[bool, str]:
        log = context.log
        pattern, described = self.pattern.of(context)
        found = pattern.find(log, context.reader)
        wanted = f"{self.counted} {described}"
        if self.count.allows(len(found)):
            return True, f"{wanted}: found {len(found)}"
        seen = {id(entry) for entry in found}  # entries of one log: none equals another
        near = [entry for entry in log if id(entry) not in seen and pattern.matches_call(entry)]
        detail = f"wanted {wanted}; found {len(found)}"
        if near:
            detail += f"; other calls to that tool: {_calls(near)}"
            if explain:
                detail += _why_not(pattern, near[0], context.reader)
        return False, detail

    def linked(self, log: Sequence[LogEntry], reader: CallReader | None) -> list[int]:
        """The matching calls; when there is none, the calls of the tool it wanted."""
        pattern = self.pattern.own
        found = pattern.find(log, reader) or [entry for entry in log if pattern.matches_call(entry)]
        return [entry.index for entry in found]


class _NoActionRule(Rule):
    def __init__(self, check: Check, pattern: ActionPattern, start: datetime) -> None:
        super().__init__(check)
        self.pattern = CompiledPattern.of(pattern, start)
        self.described = self.pattern.describe()

    def wanted(self) -> str:
        return f"no {self.described}"

    def verdict(self, context: _Context, *, explain: bool = True) -> tuple[bool, str]:
        found = self.pattern.find(context.log, context.reader)
        if not found:
            return True, f"no {self.described}"
        return False, f"forbidden {self.described} happened: {_calls(found)}"

    def linked(self, log: Sequence[LogEntry], reader: CallReader | None) -> list[int]:
        """The forbidden calls."""
        return [entry.index for entry in self.pattern.find(log, reader)]


class _StateRule(Rule):
    cost = 1

    def __init__(self, check: Check, state: StateCheck, start: datetime) -> None:
        super().__init__(check)
        self.state = state
        self.value = compile_matcher(state.value) if "value" in state.model_fields_set else None
        self.value_text = self.value.describe() if self.value is not None else ""
        self.where = _ItemCondition(state.where)
        self.condition = self.where.describe() if state.where else "(any)"
        self.count = as_count(state.count, _AT_LEAST_ONE)
        self.counted = self.count.describe()
        self.read = self.where.read()
        """The item fields the check reads: what an actor must have written for an item to be its work."""
        self.every_occurrence = self.count.max == 0 and DUE_FIELD in self.read
        """Whether a repeating item is forbidden when one of its occurrences is (:mod:`.occurrences`)."""

    def wanted(self) -> str:
        made = f", made by the {self.state.by}" if self.state.by is not None else ""
        if self.value is not None:
            return f"{self.state.path} matches {self.value_text}{made}"
        return f"{self.state.path}: {self.counted} items matching {self.condition}{made}"

    def verdict(self, context: _Context, *, explain: bool = True) -> tuple[bool, str]:
        check, start, view = self.state, context.start, context.state
        value = view.value(check.path)
        if value is MISSING:
            return False, f"{check.path} does not exist in the final state"
        makers = None if check.by is None else context.makers(check.by)
        if self.value is not None:
            passed = self.value.test(value, start)
            shown = _short({"value": value}, 120)
            verb = "matches" if passed else "does not match"
            detail = f"{check.path} {verb} {self.value_text} ({shown})"
            if explain and not passed:
                detail += f": {explaining.explain(self.value, value, start)}"
            if makers is not None:
                place = view.place(check.path)
                made = place is not None and _wrote(context.attribution, place, value, makers)
                detail += f"; {'made' if made else 'not made'} by the {check.by}"
                passed = passed and made
            return passed, detail
        items = view.items(check.path)
        if items is None:
            return (
                False,
                f"{check.path} is not a collection (it is {type(value).__name__}); use 'value' to match it",
            )
        reader = context.reader
        test = self._dated_test(context, view.place(check.path) or ())
        if self.every_occurrence:
            matching = [
                (key, record)
                for key, _, record in items
                if any(test(view, key, start, reader) for view in occurrence_records(record))
            ]
        else:
            matching = [(key, record) for key, _, record in items if test(record, key, start, reader)]
        detail = f"{check.path}: {len(matching)} of {len(items)} items match {self.condition}"
        if makers is None:
            return self.count.allows(len(matching)), f"{detail}; wanted {self.counted}"
        owned, touched = self._made(context, view.place(check.path) or (), matching, makers)
        detail += f", {owned} of them made by the {check.by}"
        if touched > owned:
            detail += f" ({touched - owned} more only changed by it)"
        count = self.count
        # The wanted work must be the actor's own (a value the check reads); a limit counts every item the
        # actor had a hand in, so a stray change to one it may not touch is not excused by who came after.
        passed = (count.min is None or owned >= count.min) and (count.max is None or touched <= count.max)
        return passed, f"{detail}; wanted {self.counted}"

    def _dated_test(self, context: _Context, place: StatePath) -> Callable[..., bool]:
        """The ``where`` test, reading an item's days and times as of when it was last written ("tonight"
        in a reminder the assistant wrote on the third day is that day's night); seed items as of the start.
        """
        where = self.where
        if not where.reads_days or not place:
            return where.test
        attribution, log = context.attribution, context.log
        # A reminder's text is read as of when it fires too ("tomorrow, Sunday" in Saturday's reminder, "in
        # six weeks" as of when written): where the two readings differ, the assistant has the benefit of
        # the doubt, so an item matches a wanted condition in either reading, an unwanted one in both.
        unwanted = self.count.max == 0
        settle = all if unwanted else any

        def test(record: Mapping[str, Any], key: str, start: datetime, reader: CallReader | None) -> bool:
            mark = attribution.mark((*place, key))
            written = _entry_time(log, mark.changed_at) if mark is not None else None
            fires = due_moment(record, written) if written is not None else None
            moments = (written,) if fires is None else (written, fires)
            return settle(_test_at(moment, record, key, start, reader) for moment in moments)

        def _test_at(
            moment: datetime | None,
            record: Mapping[str, Any],
            key: str,
            start: datetime,
            reader: CallReader | None,
        ) -> bool:
            with written_at(moment):
                return where.test(record, key, start, reader)

        return test

    def _made(
        self,
        context: _Context,
        place: StatePath,
        matching: list[tuple[str, Mapping[str, Any]]],
        makers: frozenset[Actor],
    ) -> tuple[int, int]:
        """Of the ``matching`` items, how many ``makers`` made (:meth:`_ItemCondition.made`; with no field
        read, any of the item's) and how many they had a hand in at all.
        """
        attribution, where, start, reader = context.attribution, self.where, context.start, context.reader
        made = touched = 0
        for key, record in matching:
            item = (*place, key)
            if where.fields or where.alternatives:
                written = attribution.written_by(item, self.read, makers)
                own = bool(written) and where.made(record, key, start, written, reader)
            else:
                own = _wrote(attribution, item, record, makers)
            if own:
                made += 1
                touched += 1
            elif not makers.isdisjoint(attribution.hands(item)):
                touched += 1
        return made, touched

    def places(self, view: _StateView, start: datetime, reader: CallReader) -> list[StatePath]:
        """Where the check found what it counted: the items its ``where`` matches (before ``by``), or
        the value it read.
        """
        place = view.place(self.state.path)
        if place is None:
            return []
        if self.value is not None:
            return [place]
        test = self.where.test
        return [
            (*place, key)
            for key, _, record in view.items(self.state.path) or []
            if test(record, key, start, reader)
        ]


@dataclass(frozen=True, slots=True)
class _Texts:
    """What a judge check reads: the calls with a text, and the texts it gives the judge."""

    described: str
    """The pattern, as the check's sentence names it."""
    read: list[LogEntry]
    """The matched calls that carry a text in the check's field, in log order."""
    candidates: list[tuple[tuple[int, ...], str]]
    """Each text given to the judge (or the fallback), with the log indexes of the calls it is from."""
    sent: list[datetime]
    """When each call in ``read`` was made."""
    fires: list[datetime | None] = dataclasses.field(default_factory=list)
    """For each candidate that is a reminder's text, when it fires: it is read as of then too."""

    def moments(self, index: int) -> tuple[datetime, ...]:
        """When the candidate at ``index`` is read: when sent, and for a reminder when it fires too."""
        fire = self.fires[index] if index < len(self.fires) else None
        return (self.sent[index],) if fire is None else (self.sent[index], fire)


def judged_text(args: Mapping[str, Any], field: str) -> str | None:
    """The text a judge check reads in a call's ``args``: the argument ``field``, or for an edit, the
    ``field`` among its ``updates`` (a reminder's description rewritten by ``update_reminder``).
    """
    text = args.get(field)
    if isinstance(text, str):
        return text
    updates = args.get("updates")
    changed = updates.get(field) if isinstance(updates, Mapping) else None
    return changed if isinstance(changed, str) else None


class _JudgeRule(Rule):
    cost = 2

    def __init__(self, check: Check, judge: JudgeCheck, start: datetime) -> None:
        super().__init__(check)
        self.judge = judge
        self.pattern = _Pattern(judge.action, start)
        self.fallback = compile_matcher(judge.fallback)
        self.fallback_text = self.fallback.describe()
        self.solutions: Callable[[], Sequence[str]] = tuple
        """The texts the scenario's oracle and passing variants write (set by :class:`CompiledGoals`)."""
        self.allowed: AllowedDetails | None = None
        """The details the fallback allows besides its own test (``None``: no facts, or an opt-out)."""
        if judge.facts and judge.other_details is None:
            # the facts are read once per check; the criterion and the solutions only when a text needs them
            self.allowed = AllowedDetails.of(judge.facts, start, lambda: (judge.criterion, *self.solutions()))

    def wanted(self) -> str:
        check = self.judge
        optional = ", if there is one" if check.optional else ""  # nothing sent holds
        return (
            f"'{check.field}' of {self.pattern.own_text}{optional} judged for: {check.criterion} "
            f"(without a judge model: {self.fallback_text})"
        )

    def texts(self, context: _Context) -> _Texts:
        """The texts the check reads in ``context``: each matched call's text, or all of them as one."""
        check = self.judge
        pattern, described = self.pattern.of(context)
        reader = context.reader
        found = [(entry, pattern.arguments(entry, reader)) for entry in pattern.find(context.log, reader)]
        texts = [(entry, judged_text(args, check.field)) for entry, args in found]
        read = [(entry, text) for entry, text in texts if text is not None]
        candidates: list[tuple[tuple[int, ...], str]] = [((entry.index,), text) for entry, text in read]
        if check.together and len(candidates) > 1:
            # one answer sent in parts is judged as the whole
            candidates = [(tuple(entry.index for entry, _ in read), "\n\n".join(text for _, text in read))]
        # days and times in a text are read as of when it was sent (a reminder's also as of when it fires)
        fires = [fires_at(entry) for entry, _ in read] if len(candidates) == len(read) else []
        return _Texts(described, [entry for entry, _ in read], candidates, [e.time for e, _ in read], fires)

    def judged(self, context: _Context) -> tuple[JudgedText, ...]:
        answers = context.answers
        if answers is None:
            return ()
        check, judged = self.judge, []
        for entries, text in self.texts(
            context
        ).candidates:  # one accepted text is enough: the rest were not sent
            judged.append(JudgedText(entries, answers.verdict(check.criterion, text, check.facts)))
            if judged[-1].verdict.passed:
                break
        return tuple(judged)

    def verdict(self, context: _Context, *, explain: bool = True) -> tuple[bool, str]:
        check = self.judge
        texts = self.texts(context)
        if not texts.read:
            if check.optional:  # nothing was sent, so nothing false was said
                return (
                    True,
                    f"no {texts.described} with a text in '{check.field}' (optional): nothing to judge",
                )
            return False, f"no {texts.described} with a text in '{check.field}' to judge"
        candidates = [text for _, text in texts.candidates]
        counted = f"{len(candidates)} text(s) ({', '.join(f'#{entry.index}' for entry in texts.read)})"
        if context.answers is not None:
            verdicts = [judged.verdict for judged in self.judged(context)]
            passed = verdicts[-1].passed
            said = verdicts[-1:] if passed else verdicts  # why it accepted, or why it refused each text
            reasons = [verdict.reason for verdict in said if verdict.reason]
            more = f" and {len(reasons) - _EXPLAINED} more" if len(reasons) > _EXPLAINED else ""
            detail = f"judge {'accepted' if passed else 'rejected'} {counted} for: {check.criterion}"
            return passed, detail + "".join(f"{JUDGE_SAID}{reason}" for reason in reasons[:_EXPLAINED]) + more
        sent = texts.sent
        moments = [texts.moments(index) for index in range(min(len(candidates), len(sent)))]
        holds = [
            any(self._holds(text, at, context.start) for at in when)
            for text, when in zip(candidates, moments, strict=False)
        ]
        passed = any(holds)
        verdict = "holds" if passed else "fails"
        detail = f"no judge model; fallback {self.fallback_text} {verdict} on {counted}"
        if passed and self.allowed is not None:  # as the judge would: a detail the facts lack fails
            strays = [
                self._stray_at(text, when, context) if held else None
                for text, when, held in zip(candidates, moments, holds, strict=False)
            ]
            if not any(held and stray is None for held, stray in zip(holds, strays, strict=True)):
                rejected = [stray for stray in strays if stray is not None]
                more = f" and {len(rejected) - 1} more" if len(rejected) > 1 else ""
                return False, f"no judge model; {rejected[0]}{more}"
        if explain and not passed:
            shown = []
            for text, at in zip(candidates[:_EXPLAINED], sent, strict=False):
                with written_at(at):
                    shown.append(f"{quote(text)}: {explaining.explain(self.fallback, text, context.start)}")
            more = f" and {len(candidates) - _EXPLAINED} more" if len(candidates) > _EXPLAINED else ""
            detail += ": " + " / ".join(shown) + more
        return passed, detail

    def linked(self, log: Sequence[LogEntry], reader: CallReader | None) -> list[int]:
        """The matching calls that carry a text to judge."""
        pattern, field = self.pattern.own, self.judge.field
        found = pattern.find(log, reader)
        return [e.index for e in found if judged_text(pattern.arguments(e, reader), field) is not None]

    def _stray(
        self, text: str, sent: datetime, context: _Context, read_at: datetime | None = None
    ) -> str | None:
        """Why the facts rule rejects ``text`` sent at ``sent`` (read as of ``read_at``: a reminder's when it
        fires) for a detail neither an allowed text gives nor the episode did ("your cab comes at 09:40"
        where the ride booked is at 09:40), if so.
        """
        if self.allowed is None:
            return None
        found = self.allowed.stray(text, sent, also=partial(self._given_elsewhere, context), read_at=read_at)
        if found is None:
            return None
        return f"{quote(found.around)} states {found.detail.shown}, {found.why}"

    def _stray_at(self, text: str, moments: tuple[datetime, ...], context: _Context) -> str | None:
        """Why the facts rule rejects ``text`` read as of each of ``moments`` (``None`` when one reading
        is clean).
        """
        found = None
        for at in moments:  # the day it is sent is no stray detail; the day a reminder fires may be one
            found = self._stray(text, moments[0], context, read_at=at)
            if found is None:
                return None
        return found

    @staticmethod
    def _given_elsewhere(context: _Context, detail: Detail, sent: datetime) -> bool:
        """Whether the assistant did what ``detail`` states (a text telling what was done states no detail
        the facts contradict: whether it was right to do is the state checks' business).
        """
        return context.done().allows_read(detail, sent)

    def _holds(self, text: str, sent: datetime, start: datetime) -> bool:
        """Whether the fallback accepts ``text`` read as of ``sent`` (a text in parts: as of its first)."""
        with written_at(sent):
            return self.fallback.test(text, start)


class _AnyOfRule(Rule):
    """One of several ways holds, each way all of its checks (a choice the story leaves open)."""

    def __init__(self, check: Check, ways: AnyOfChecks, start: datetime) -> None:
        super().__init__(check)
        self.ways = [[_rule(option, start) for option in way.all_of] for way in ways.root]
        self.cost = max(rule.cost for way in self.ways for rule in way)

    def wanted(self) -> str:
        return "one of: " + " | or: ".join(" and ".join(rule.wanted() for rule in way) for way in self.ways)

    def verdict(self, context: _Context, *, explain: bool = True) -> tuple[bool, str]:
        refused = []
        for number, way in enumerate(self.ways, start=1):
            said = [rule.verdict(context, explain=explain) for rule in way]
            if all(passed for passed, _ in said):
                return True, f"way {number} of {len(self.ways)} holds: " + "; ".join(text for _, text in said)
            refused.append(f"way {number}: " + "; ".join(text for passed, text in said if not passed))
        return False, "no way holds: " + " | ".join(refused)

    def linked(self, log: Sequence[LogEntry], reader: CallReader | None) -> list[int] | None:
        found = [rule.linked(log, reader) for way in self.ways for rule in way]
        if all(indexes is None for indexes in found):
            return None
        return sorted({index for indexes in found if indexes for index in indexes})

    def places(self, view: _StateView, start: datetime, reader: CallReader) -> list[StatePath] | None:
        found = [rule.places(view, start, reader) for way in self.ways for rule in way]
        if all(places is None for places in found):
            return None
        return list(dict.fromkeys(place for places in found if places for place in places))


def _entry_time(log: Sequence[LogEntry], index: int) -> datetime | None:
    """When the log entry at ``index`` happened (``None`` if the log does not hold it)."""
    if 0 <= index < len(log) and log[index].index == index:
        return log[index].time
    return next((entry.time for entry in log if entry.index == index), None)


def _rule(check: Check, start: datetime) -> Rule:
    return CHECK_FORMS[check.form].rule(check, check.body, start)


class CompiledGoals:
    """A scenario's goals with their checks compiled: matchers, patterns and the fixed parts of their
    descriptions, made once per scenario instead of on every evaluation.
    """

    def __init__(self, scenario: Scenario) -> None:
        self.files = FileIdentity.of(scenario)
        """The scenario's world files, by which attached paths are read (a file is its content)."""
        self.goals = tuple(
            (goal, tuple(_rule(check, scenario.start) for check in goal.checks)) for goal in scenario.goals
        )
        people: tuple[NameFinder, frozenset[str]] | None = None
        for _, rules in self.goals:
            for rule in rules:
                if isinstance(rule, _JudgeRule):  # read only when a text states a detail the facts lack
                    rule.solutions = partial(solution_texts, scenario, rule.judge.field)
                    if rule.allowed is not None:  # a wrong person is a wrong detail where the facts name one
                        if people is None:
                            people = NameFinder.of(known_names(scenario.seed)), owner_names(scenario.seed)
                        rule.allowed.know_people(*people)
        self.cheapest_first = tuple(
            sorted((rule for _, rules in self.goals for rule in rules), key=lambda rule: rule.cost)
        )


@dataclass(frozen=True, slots=True)
class FallbackTexts:
    """What one judge check with facts reads in an episode, for measuring the facts rule."""

    goal: str
    check: JudgeCheck
    allowed: AllowedDetails
    texts: tuple[tuple[str, datetime], ...]
    """Each text the fallback reads, with when it was sent."""


def fallback_texts(
    scenario: Scenario, log: Sequence[LogEntry], state: Mapping[str, Any]
) -> list[FallbackTexts]:
    """The texts each judge check of ``scenario`` that reads its facts (no ``other_details``) reads in an
    episode's ``log`` and final ``state``.
    """
    view = _StateView(state)
    compiled = compiled_goals(scenario)
    context = _Context(
        scenario.start, log, view, Attribution(), None, CallReader.of_state(view.whole, compiled.files)
    )
    found = []
    for goal, rules in compiled.goals:
        for rule in rules:
            if isinstance(rule, _JudgeRule) and rule.allowed is not None:
                texts = rule.texts(context)
                read = tuple(zip((text for _, text in texts.candidates), texts.sent, strict=False))
                found.append(FallbackTexts(goal.id, rule.judge, rule.allowed, read))
    return found


def check_sentences(scenario: Scenario) -> dict[str, list[str]]:
    """Each goal's checks as sentences, by goal id: the check's own ``description`` when it has one, then
    what the check looks for (``pare scenarios review`` shows them).
    """
    sentences: dict[str, list[str]] = {}
    for goal, rules in compiled_goals(scenario).goals:
        sentences[goal.id] = [
            f"{rule.description.rstrip('. ')}: {rule.wanted()}" if rule.description else rule.wanted()
            for rule in rules
        ]
    return sentences


def compiled_goals(scenario: Scenario) -> CompiledGoals:
    """``scenario``'s goals compiled, once per scenario object: every episode of it, and every idle turn
    of one that ends when met, evaluates the same checks.
    """
    return scenario.derived(CompiledGoals, lambda: CompiledGoals(scenario))


_EXPLAINED = 3
"""How many of a failing judge check's texts are explained one by one."""

JUDGE_SAID = " | the judge: "
"""What precedes each of the judge's reasons in a judge check's sentence (pages that show the reasons
apart split the sentence there)."""


def _why_not(pattern: CompiledPattern, entry: LogEntry, reader: CallReader) -> str:
    """Why the call ``entry`` (of the right tool) does not match ``pattern``: its arguments' reasons."""
    args = pattern.arguments(entry, reader)
    reasons = [
        f"{name}: {why}"
        for name, matcher in pattern.args
        if (why := explaining.explain(matcher, args.get(name), pattern.start))
    ]
    if not pattern.tells(entry, reader):
        via = pattern.pattern.via
        channels = f" via {' or '.join(via)}" if via else ""
        reasons.insert(0, f"it did not tell {pattern.pattern.to}{channels}")
    return f"; #{entry.index} does not match: {'; '.join(reasons)}" if reasons else ""


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


_NO_FIELDS: Mapping[str, Any] = MappingProxyType({})


def _wrote(attribution: Attribution, place: StatePath, value: Any, makers: frozenset[Actor]) -> bool:
    """Whether ``makers`` wrote ``value`` (at ``place``), read as a whole: one of its fields if it is a
    record, else the value itself (who last set it).
    """
    if isinstance(value, Mapping) and value:
        return bool(attribution.written_by(place, [str(name) for name in value], makers))
    writer = attribution.writer(place)
    return writer is not None and writer in makers


def _record(item: Any) -> Mapping[str, Any]:
    """What an item's fields are read from: the item if it is a mapping, else nothing."""
    return item if type(item) is dict or isinstance(item, Mapping) else _NO_FIELDS


class _ItemCondition:
    """A state check's ``where``: every field's matcher holds, and of an ``any_of`` list one mapping does."""

    def __init__(self, where: Mapping[str, Any]) -> None:
        self.fields = tuple((name, compile_matcher(raw)) for name, raw in where.items() if name != WHERE_ANY)
        self.alternatives = tuple(_ItemCondition(item) for item in where.get(WHERE_ANY, ()))
        cheapest_first = sorted(self.fields, key=lambda field: field[1].cost)
        self.tests = tuple(
            (None if name == WHERE_KEY else name, matcher.test) for name, matcher in cheapest_first
        )
        """Each field's test (its name, ``None`` for the item's key), in the order they are run: most
        items fail a cheap comparison of one field."""
        self.reads_days: bool = any(matcher.reads_days for _, matcher in self.fields) or any(
            option.reads_days for option in self.alternatives
        )
        """Whether it reads days or times in text, which are counted from when the item was written."""

    def test(
        self, record: Mapping[str, Any], key: str, start: datetime, reader: CallReader | None = None
    ) -> bool:
        """Whether the item of this ``record`` (:func:`_record`) and ``key`` meets the condition; with
        ``reader``, attached files are read by their content (:mod:`~pare.scenarios.file_identity`).
        """
        for name, test in self.tests:  # a loop, not all(): it runs for every item of every check
            value = key if name is None else item_text(record) if name == WHERE_TEXT else record.get(name)
            if reader is not None and name in ATTACHMENT_FIELDS:
                value = reader.attached(value)
            if not test(value, start):
                return False
        return not self.alternatives or any(
            option.test(record, key, start, reader) for option in self.alternatives
        )

    def read(self) -> tuple[str, ...]:
        """The field names the condition reads, its ``any_of`` alternatives' included (``_key``, the
        item's identity, is set by whoever created the item).
        """
        names = dict.fromkeys(name for name, _ in self.fields)
        for option in self.alternatives:
            names.update(dict.fromkeys(option.read()))
        return tuple(names)

    def made(
        self,
        record: Mapping[str, Any],
        key: str,
        start: datetime,
        written: frozenset[str],
        reader: CallReader | None = None,
    ) -> bool:
        """Whether an item that meets the condition meets it by what an actor wrote (its ``written``
        fields): one of the fields it reads, or in each ``any_of`` alternative that holds, since one that
        holds without the actor's values would have held had it written nothing.
        """
        if any(name in written for name, _ in self.fields):
            return True
        holding = [option for option in self.alternatives if option.test(record, key, start, reader)]
        return bool(holding) and all(option.made(record, key, start, written, reader) for option in holding)

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


@dataclass(frozen=True, slots=True)
class CheckForm:
    """One form of check, by its key in a scenario file: what it is written as, what it compiles to and
    what the loader asks of it. Every part of PARE that handles checks as such reads :data:`CHECK_FORMS`.
    """

    key: str
    """Its key in a check (``action``); :class:`~pare.scenarios.model.Check` has a field of that name."""
    model: type[BaseModel]
    """What it is written as (the type of that field)."""
    rule: Callable[[Check, Any, datetime], Rule]
    """Its compiled rule, ``rule(check, body, start)`` (``body``: the check's part of this form)."""
    positive: Callable[[Any], bool]
    """Whether a check of this form demands that something be there (a goal needs one such check)."""
    needs_assistant: Callable[[Any], bool]
    """Whether a positive check of this form can hold only through the assistant's own work (a scenario
    needs one such check)."""
    about_the_assistant: Callable[[Any], bool] = lambda body: False
    """Whether the check is about who did the work, so that it is asked again crediting the user's work
    to the assistant (``user_made``); a judge check reads a text, not who wrote it."""


CHECK_FORMS: dict[str, CheckForm] = {}
"""Every form of check by its key, in the order :class:`~pare.scenarios.model.Check` declares them."""


def register_check_form(form: CheckForm) -> None:
    """Make ``form`` a form of check: its rule compiles and judges the checks of that key.

    Raises ``ValueError`` when the key is taken or is not a field of :class:`~pare.scenarios.model.Check`
    of the form's model (the field is what lets a scenario file write it).
    """
    if form.key in CHECK_FORMS:
        raise ValueError(f"check form '{form.key}' is already registered")
    declared = Check.model_fields.get(form.key) if form.key in CHECK_FORM_KEYS else None
    if declared is None or form.model not in typing.get_args(declared.annotation):
        raise ValueError(f"a check form needs its field on Check: '{form.key}: {form.model.__name__} | None'")
    CHECK_FORMS[form.key] = form


def _positive(check: Check) -> bool:
    form = CHECK_FORMS[check.form]
    return form.positive(check.body)


def _about_the_assistant(check: Check) -> bool:
    return CHECK_FORMS[check.form].about_the_assistant(check.body)


def _needs_assistant(check: Check) -> bool:
    form = CHECK_FORMS[check.form]
    return form.positive(check.body) and form.needs_assistant(check.body)


def _at_least_one(count: int | Count | None) -> bool:
    """Whether a check's ``count`` (default: at least one) wants at least one."""
    if count is None:
        return True
    return (count if isinstance(count, int) else (as_count(count, count).min or 0)) >= 1


def _assistants(pattern: ActionPattern) -> bool:
    return pattern.actor == "assistant"


def _by_the_assistant(state: StateCheck) -> bool:
    return state.by == "assistant"


for _form in (
    CheckForm(
        "action",
        ActionCheck,
        _ActionRule,
        positive=lambda action: _at_least_one(action.count),
        needs_assistant=_assistants,
        about_the_assistant=_assistants,
    ),
    CheckForm(
        "no_action",
        ActionPattern,
        _NoActionRule,
        positive=lambda pattern: False,
        needs_assistant=lambda pattern: False,
    ),
    CheckForm(
        "state",
        StateCheck,
        _StateRule,
        positive=lambda state: "value" in state.model_fields_set or _at_least_one(state.count),
        needs_assistant=_by_the_assistant,
        about_the_assistant=_by_the_assistant,
    ),
    CheckForm(
        "judge",
        JudgeCheck,
        _JudgeRule,
        positive=lambda judge: not judge.optional,  # a text that meets its criterion must be there
        needs_assistant=lambda judge: _assistants(judge.action),
    ),
    CheckForm(
        "any_of",
        AnyOfChecks,
        _AnyOfRule,
        # a choice demands something when every way does, and needs the assistant when every way does
        positive=lambda ways: all(any(_positive(check) for check in way.all_of) for way in ways.root),
        needs_assistant=lambda ways: all(
            any(_needs_assistant(check) for check in way.all_of) for way in ways.root
        ),
        about_the_assistant=lambda ways: any(
            CHECK_FORMS[check.form].about_the_assistant(check.body)
            for way in ways.root
            for check in way.all_of
        ),
    ),
):
    register_check_form(_form)
