"""Turning a scenario into a ready environment: apps seeded, events scheduled.

Everything an episode's world starts from depends on the scenario alone: which apps it has, the seed data
validated into the apps' states, the scheduled events with their times resolved and their triggers'
patterns compiled. That is worked out once per scenario (its :class:`_Blueprint`, made while the first
episode's environment is built) and every episode gets its own copy of what it can change: fresh app
states and fresh event arguments. Only immutable parts (compiled patterns, times, the pickled states)
are shared between episodes.
"""

from __future__ import annotations

import asyncio
from collections.abc import Sequence
from dataclasses import dataclass, replace
from datetime import timedelta
from typing import Any

from pare.apps.base import SeedState
from pare.apps.registry import CORE_APPS
from pare.env import EnvConfig, Environment
from pare.errors import SimulationBug, first_error
from pare.scenarios.checks import Judge, JudgeVerdict, Question
from pare.scenarios.file_identity import FileIdentity
from pare.scenarios.model import ActionPattern, Event, EventJudge, Scenario
from pare.scenarios.patterns import CompiledPattern, event_positions
from pare.scenarios.reading import CallReader, register_live
from pare.scenarios.seed import prepare_seed
from pare.scenarios.times import parse_duration, parse_time, resolve_relative_times
from pare.sim.events import AfterEvent, AtTime, EventAction, ScheduledEvent, Trigger, WhenLogged
from pare.sim.log import ActionLog, LogEntry


def build_environment(
    scenario: Scenario, config: EnvConfig | None = None, *, readings: EventReadings | None = None
) -> Environment:
    """An environment for ``scenario``: its apps (plus the core ones), seed data and scheduled events.

    The episode starts at the scenario's start time whatever ``config`` says; everything else (seed,
    tool failures, noise, notifications) comes from ``config``. With ``readings`` (the run's judge model,
    asked by whoever drives the episode), reactive events with a ``judge`` read the text the user or the
    assistant wrote through it; without, by their ``if_args``.
    """
    settings = (config or EnvConfig()).model_copy(update={"start_time": scenario.start})
    blueprint: _Blueprint | None = scenario.known(_Blueprint)
    if blueprint is None:
        env = Environment([app for app in scenario.all_apps if app not in CORE_APPS], settings)
        # The first episode of a scenario validates and checks its seed (errors are raised here, and
        # again for every later build, since nothing is kept); its loaded states become the blueprint.
        env.load({app: prepare_seed(app, data, scenario.start)[0] for app, data in scenario.seed.items()})
        blueprint = scenario.keep(_Blueprint, _Blueprint.of(scenario, env))
    else:
        env = Environment(blueprint.apps, settings)
        blueprint.seed(env)
    reader = register_live(env, blueprint.files)
    for plan in blueprint.events:
        for scheduled in plan.scheduled(env, reader, readings):
            env.schedule(scheduled)
    env.scheduler.validate()
    return env


# -- what every episode of a scenario starts from -----------------------------------------------------
@dataclass(frozen=True, slots=True)
class _Timed:
    """An event at a time, or after another event: the same for every episode but its arguments' copy."""

    event: ScheduledEvent

    def scheduled(
        self, env: Environment, reader: CallReader, readings: EventReadings | None
    ) -> list[ScheduledEvent]:
        event = self.event
        action = EventAction(event.action.app, event.action.tool, _fresh(event.action.args))
        return [ScheduledEvent(event.event_id, event.trigger, action)]


@dataclass(frozen=True, slots=True)
class _Reactive:
    """A reactive event (``when``) as compiled once: its patterns, delays, calls and descriptions. Each
    episode binds it to its own environment (:class:`_Trigger`), which the trigger reads (the log, what
    still waits).
    """

    event_id: str
    delay: timedelta
    pattern: CompiledPattern
    if_args: CompiledPattern
    action: EventAction
    description: str
    otherwise: _Otherwise | None
    judged: EventJudge | None
    """What the triggering text must mean, for a judge model (:class:`~pare.scenarios.model.EventJudge`)."""
    unjudged: CompiledPattern
    """``if_args`` without the judged field: what the judge's verdict is combined with."""

    def scheduled(
        self, env: Environment, reader: CallReader, readings: EventReadings | None
    ) -> list[ScheduledEvent]:
        trigger = _Trigger(self, env.log, reader, readings if self.judged is not None else None)
        action = EventAction(self.action.app, self.action.tool, _fresh(self.action.args))
        condition = WhenLogged(trigger.meets, self.delay, self.description)
        events = [ScheduledEvent(self.event_id, condition, action)]
        otherwise = self.otherwise
        if otherwise is not None:
            call = otherwise.action
            reaction = EventAction(call.app, call.tool, _fresh(call.args))
            condition = WhenLogged(trigger.misses, otherwise.delay, otherwise.description)
            # a first message that says too little is answered with a question only if the rest of the
            # answer has not come by the time the question would be sent
            events.append(ScheduledEvent(otherwise.event_id, condition, reaction, withdrawn_by=self.event_id))
        return events


@dataclass(frozen=True, slots=True)
class _Otherwise:
    """The reaction of a reactive event to a triggering action that does not meet its ``if_args``."""

    event_id: str
    delay: timedelta
    action: EventAction
    description: str


@dataclass(frozen=True, slots=True)
class _Blueprint:
    """A scenario's world before its first call, shared (read only) by all its episodes."""

    apps: tuple[str, ...]
    """The apps besides the core ones."""
    states: tuple[tuple[str, SeedState], ...]
    """Each seeded app's state as loaded (validated and checked), pickled: unpickling gives an episode
    an exact copy of its own, for less than validating the seed again, and only if the episode reads
    the app's data at all; with the snapshot it gives, for the apps it never reads."""
    events: tuple[_Timed | _Reactive, ...]
    """The scenario's events in its order (which decides the order of events due at the same time)."""
    files: FileIdentity
    """The scenario's world files, by which the world reads attached paths (a file is its content)."""

    @classmethod
    def of(cls, scenario: Scenario, env: Environment) -> _Blueprint:
        """The blueprint of ``scenario``, from ``env``: an environment for it whose seed was just loaded."""
        return cls(
            apps=tuple(app for app in scenario.all_apps if app not in CORE_APPS),
            states=tuple((app, SeedState.of(env.apps[app].state)) for app in scenario.seed),
            events=tuple(_plan(event, scenario) for event in scenario.events),
            files=FileIdentity.of(scenario),
        )

    def seed(self, env: Environment) -> None:
        """Give each seeded app of ``env`` its seed state (its own copy, made if it reads it)."""
        for app, state in self.states:
            env.app(app).adopt_seed(state)


def _fresh(value: Any) -> Any:
    """A copy of JSON-like ``value`` (an event's arguments) with its own lists and dicts: an episode's
    calls never share a container with another episode's.
    """
    if isinstance(value, dict):
        return {key: _fresh(item) for key, item in value.items()}
    if isinstance(value, list):
        return [_fresh(item) for item in value]
    return value


# -- events -------------------------------------------------------------------------------------------
def _plan(event: Event, scenario: Scenario) -> _Timed | _Reactive:
    """A scenario event compiled: its times resolved against the start, its patterns compiled."""
    app, _, tool = event.tool.partition("__")
    action = EventAction(app, tool, resolve_relative_times(event.args, scenario.start))
    if event.when is None:
        return _Timed(ScheduledEvent(event.id, _timed_trigger(event, scenario), action))
    delay = parse_duration(event.delay)
    pattern = CompiledPattern.of(event.when, scenario.start)
    if_args = CompiledPattern.of(ActionPattern(actor="any", ok=None, args=event.if_args), scenario.start)
    unjudged = if_args
    if event.judge is not None:
        rest = {name: matcher for name, matcher in event.if_args.items() if name != event.judge.field}
        unjudged = CompiledPattern.of(ActionPattern(actor="any", ok=None, args=rest), scenario.start)
    otherwise, otherwise_id, reaction = event.otherwise, event.otherwise_id, None
    if otherwise is not None and otherwise_id is not None:
        app, _, tool = otherwise.tool.partition("__")
        wanted = ", ".join(f"{name}: {matcher.describe()}" for name, matcher in if_args.args)
        reaction = _Otherwise(
            event_id=otherwise_id,
            delay=delay if otherwise.delay is None else parse_duration(otherwise.delay),
            action=EventAction(app, tool, resolve_relative_times(otherwise.args, scenario.start)),
            description=f"{pattern.describe()} but not {wanted}",
        )
    return _Reactive(
        event.id, delay, pattern, if_args, action, pattern.describe(), reaction, event.judge, unjudged
    )


_TOLD_TEXT = ("content",)
"""The argument that carries what a person was told: read together over a reactive event's triggers."""


class EventReadings:
    """The judge's readings of the triggering texts of reactive events, in one episode.

    A trigger is tested as the action is logged, synchronously, but a model judge is awaited: a trigger
    whose text has no verdict yet asks for one here and cannot tell yet (the scheduler holds it). Whoever
    drives the episode then awaits :meth:`ask` and has the scheduler test the trigger again
    (:meth:`~pare.sim.events.EventScheduler.retest`), before the clock moves.
    """

    def __init__(self, judge: Judge) -> None:
        self.judge = judge
        self._known: dict[Question, JudgeVerdict] = {}
        self._waiting: dict[Question, None] = {}
        """The questions asked and not answered yet, in the order they were asked."""

    def verdict(self, judged: EventJudge, text: str) -> JudgeVerdict | None:
        """The judge's verdict on ``text`` for ``judged``, or ``None`` (asked for) while it is not known."""
        question = (judged.criterion, text, tuple(judged.facts))
        known = self._known.get(question)
        if known is None:
            self._waiting[question] = None
        return known

    async def ask(self) -> None:
        """Ask the judge every question waiting (side by side)."""
        waiting, self._waiting = list(self._waiting), {}
        if not waiting:
            raise SimulationBug("a reactive event waits for the judge but asked it nothing")
        try:
            async with asyncio.TaskGroup() as group:
                tasks = [group.create_task(self.judge(*question)) for question in waiting]
        except BaseExceptionGroup as errors:  # the call's own error (a provider down, a cache miss)
            raise first_error(errors) from None
        self._known.update(zip(waiting, (task.result() for task in tasks), strict=True))


@dataclass(frozen=True, slots=True)
class Disagreement:
    """A triggering action that a reactive event's rule (``if_args``) and the judge model read apart."""

    event_id: str
    entry: int
    """The log index of the triggering action."""
    text: str
    """What it wrote."""
    rule: bool
    """Whether ``if_args`` holds."""
    judge: bool
    """Whether the judge's reading (with the rest of ``if_args``) holds."""
    reason: str

    def describe(self) -> str:
        """One line: which event, which action, who says what."""
        said = f" ({self.reason})" if self.reason else ""
        text = self.text if len(self.text) <= 80 else self.text[:77] + "..."
        rule, judge = ("yes" if verdict else "no" for verdict in (self.rule, self.judge))
        where = f"event '{self.event_id}' on #{self.entry} {text!r}"
        return f"{where}: the rule says {rule}, the judge {judge}{said}"


async def disagreements(scenario: Scenario, log: Sequence[LogEntry], judge: Judge) -> list[Disagreement]:
    """Where the rule and the judge read the triggering actions in ``log`` apart, for each reactive event of
    ``scenario`` with a ``judge`` (every triggering action the user or the assistant made, whether or not
    the event had fired by then).
    """
    found = []
    positions = event_positions(log)
    for event in scenario.events:
        judged = event.judge
        if judged is None:
            continue
        plan = _plan(event, scenario)
        assert isinstance(plan, _Reactive)
        for entry in log:
            text = entry.args.get(judged.field)
            if (
                entry.actor == "env"
                or not isinstance(text, str)
                or not plan.pattern.matches(entry, positions)
            ):
                continue
            rule = plan.if_args.matches_args(entry)
            verdict = await judge(judged.criterion, text, judged.facts)
            reading = verdict.passed and plan.unjudged.matches_args(entry)
            if reading != rule:
                found.append(Disagreement(event.id, entry.index, text, rule, reading, verdict.reason))
    return found


def _timed_trigger(event: Event, scenario: Scenario) -> Trigger:
    if event.at is not None:
        return AtTime(parse_time(event.at, scenario.start))
    assert event.after is not None
    return AfterEvent(event.after, parse_duration(event.delay))


class _Trigger:
    """A reactive event's trigger in one episode: the action it waits for, and what that action must say.

    It reads the episode's log (when events fired) but holds nothing that holds it back: the scheduler
    keeps the trigger, so a reference to the environment would make a cycle that keeps the episode's
    world in memory until the cyclic garbage collector runs.
    """

    def __init__(
        self, plan: _Reactive, log: ActionLog, reader: CallReader, readings: EventReadings | None = None
    ) -> None:
        self.plan = plan
        self.log = log
        self.reader = reader
        """Reads what a triggering call told whom, and its attached files, from the apps just after it."""
        self.readings = readings
        """The run's judge model's readings, for an event whose ``if_args`` on free text it reads instead."""
        self.met = False
        """Whether the event's condition has been met: the scheduler stops waiting (and schedules the
        event) on the first entry it :meth:`meets`."""
        self._last: tuple[LogEntry, bool, bool] | None = None
        """The latest entry tested and its verdicts: the event and its ``otherwise`` test the same entry."""

    def _verdicts(self, entry: LogEntry) -> tuple[bool, bool | None]:
        """Whether ``entry`` is a triggering action, and whether its arguments meet ``if_args`` (``None``
        while the judge's reading of its text is being asked).
        """
        last = self._last
        if last is not None and last[0] is entry:  # entries are immutable and the log only grows
            return last[1], last[2]
        pattern, reader = self.plan.pattern, self.reader
        triggers = pattern.matches_call(entry) and pattern.matches(
            entry, event_positions(self.log) if pattern.needs_event_positions else None, reader
        )
        meets_if = self._meets_if(entry) if triggers else False
        if meets_if is not None:
            self._last = (entry, triggers, meets_if)
        return triggers, meets_if

    def _meets_if(self, entry: LogEntry) -> bool | None:
        """Whether a triggering ``entry`` says what ``if_args`` wants: by the judge model where the event
        has one and the user or the assistant wrote the text (the world's own texts are the scenario's,
        which the rule reads exactly), else by the matchers; ``None`` while the judge is being asked.
        """
        plan, readings, reader = self.plan, self.readings, self.reader
        # with 'to', the reply reads what the person got: a forward's text is the forwarded email
        told = plan.pattern.people is not None
        judged = plan.judged
        text = entry.args.get(judged.field) if judged is not None else None
        if readings is None or judged is None or entry.actor == "env" or not isinstance(text, str):
            if plan.if_args.matches_args(entry, reader, told=told):
                return True
            together = self._told_together(entry) if told else None
            return together is not None and plan.if_args.matches_args(together)
        if plan.unjudged.matches_args(entry, reader, told=told):
            verdict = readings.verdict(judged, text)
            if verdict is None or verdict.passed:  # not known yet, or this message alone says it
                return None if verdict is None else True
        # a reply waits for the facts, not for them to come in one message
        together = self._told_together(entry) if told else None
        if together is None or not isinstance(joined := together.args.get(judged.field), str):
            return False
        if not plan.unjudged.matches_args(together):
            return False
        verdict = readings.verdict(judged, joined)
        return None if verdict is None else verdict.passed

    def _told_together(self, entry: LogEntry) -> LogEntry | None:
        """``entry`` as everything the person of ``to`` was told by the triggering calls so far, its text
        the texts of all of them in the order sent (``None`` when it is the first): a reply waits for the
        facts, not for them to come in one message.
        """
        pattern, reader = self.plan.pattern, self.reader
        events = event_positions(self.log) if pattern.needs_event_positions else None
        earlier = [
            before
            for before in self.log
            if before.index < entry.index and pattern.matches(before, events, reader)
        ]
        if not earlier:
            return None
        said = [reader.args(call, told=True) for call in (*earlier, entry)]
        args = dict(said[-1])
        for name in _TOLD_TEXT:
            texts = [text for call in said if isinstance(text := call.get(name), str)]
            if len(texts) > 1:
                args[name] = "\n\n".join(texts)
        return replace(entry, args=args)

    def meets(self, entry: LogEntry) -> bool | None:
        triggers, meets_if = self._verdicts(entry)
        if triggers and meets_if:
            self.met = True
            return True
        return meets_if if triggers else False

    def misses(self, entry: LogEntry) -> bool | None:
        # only while the event itself still waits: once it was met, the world has answered (an entry that
        # meets the event is never a miss, so the order in which the two are tested does not matter)
        if self.met:
            return False
        triggers, meets_if = self._verdicts(entry)
        if not triggers:
            return False
        return None if meets_if is None else not meets_if
