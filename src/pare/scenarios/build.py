"""Turning a scenario into a ready environment: apps seeded, events scheduled."""

from __future__ import annotations

from typing import Any

from pare.apps.registry import CORE_APPS
from pare.env import EnvConfig, Environment
from pare.scenarios.model import ActionPattern, Event, Scenario
from pare.scenarios.patterns import CompiledPattern, event_positions
from pare.scenarios.seed import prepare_seed
from pare.scenarios.times import parse_duration, parse_time, resolve_relative_times
from pare.sim.events import AfterEvent, AtTime, EventAction, ScheduledEvent, Trigger, WhenLogged
from pare.sim.log import LogEntry


def build_environment(scenario: Scenario, config: EnvConfig | None = None) -> Environment:
    """An environment for ``scenario``: its apps (plus the core ones), seed data and scheduled events.

    The episode starts at the scenario's start time whatever ``config`` says; everything else (seed,
    tool failures, noise, notifications) comes from ``config``.
    """
    settings = (config or EnvConfig()).model_copy(update={"start_time": scenario.start})
    env = Environment([app for app in scenario.all_apps if app not in CORE_APPS], settings)
    env.load(_prepared_seed(scenario))
    for event in scenario.events:
        for scheduled in scheduled_events(event, scenario, env):
            env.schedule(scheduled)
    env.scheduler.validate()
    return env


_PREPARED: dict[int, tuple[Scenario, dict[str, dict[str, Any]]]] = {}
"""Each scenario's seed in the apps' formats, by the scenario object's id (kept with it, so the id is
not reused while the entry lives)."""


def _prepared_seed(scenario: Scenario) -> dict[str, dict[str, Any]]:
    """The scenario's seed data in the apps' formats, relative times resolved: worked out once per
    scenario, since every episode of it starts from the same data. Loading validates it into fresh
    app states each time, so episodes share nothing.
    """
    known = _PREPARED.get(id(scenario))
    if known is not None and known[0] is scenario:
        return known[1]
    seed = {app: prepare_seed(app, data, scenario.start)[0] for app, data in scenario.seed.items()}
    if len(_PREPARED) >= 1024:  # a long-lived process that loads scenarios again and again
        _PREPARED.clear()
    _PREPARED[id(scenario)] = (scenario, seed)
    return seed


def scheduled_events(event: Event, scenario: Scenario, env: Environment) -> list[ScheduledEvent]:
    """The kernel events for a scenario event: the event itself, and its ``otherwise`` reaction if any."""
    app, _, tool = event.tool.partition("__")
    action = EventAction(app, tool, resolve_relative_times(event.args, scenario.start))
    if event.when is None:
        return [ScheduledEvent(event.id, _timed_trigger(event, scenario), action)]
    trigger = _Trigger(event, scenario, env)
    events = [ScheduledEvent(event.id, WhenLogged(trigger.meets, trigger.delay, trigger.describe()), action)]
    otherwise, otherwise_id = event.otherwise, event.otherwise_id
    if otherwise is not None and otherwise_id is not None:
        app, _, tool = otherwise.tool.partition("__")
        reaction = EventAction(app, tool, resolve_relative_times(otherwise.args, scenario.start))
        delay = trigger.delay if otherwise.delay is None else parse_duration(otherwise.delay)
        description = f"{trigger.describe()} but not {trigger.describe_if()}"
        events.append(ScheduledEvent(otherwise_id, WhenLogged(trigger.misses, delay, description), reaction))
    return events


def _timed_trigger(event: Event, scenario: Scenario) -> Trigger:
    if event.at is not None:
        return AtTime(parse_time(event.at, scenario.start))
    assert event.after is not None
    return AfterEvent(event.after, parse_duration(event.delay))


class _Trigger:
    """A reactive event's trigger: the action it waits for, and what that action must say."""

    def __init__(self, event: Event, scenario: Scenario, env: Environment) -> None:
        assert event.when is not None
        self.event_id = event.id
        self.delay = parse_duration(event.delay)
        self.pattern = CompiledPattern.of(event.when, scenario.start)
        self.if_args = CompiledPattern.of(
            ActionPattern(actor="any", ok=None, args=event.if_args), scenario.start
        )
        self.env = env

    def triggers(self, entry: LogEntry) -> bool:
        if not self.pattern.matches_call(entry):
            return False
        events = event_positions(self.env.log) if self.pattern.needs_event_positions else None
        return self.pattern.matches(entry, events)

    def meets(self, entry: LogEntry) -> bool:
        return self.triggers(entry) and self.if_args.matches_args(entry)

    def misses(self, entry: LogEntry) -> bool:
        # only while the event itself still waits: once it has fired, the world has answered
        waiting = self.event_id in self.env.scheduler.waiting_on_conditions
        return waiting and self.triggers(entry) and not self.if_args.matches_args(entry)

    def describe(self) -> str:
        return self.pattern.describe()

    def describe_if(self) -> str:
        return ", ".join(f"{name}: {matcher.describe()}" for name, matcher in self.if_args.args)
