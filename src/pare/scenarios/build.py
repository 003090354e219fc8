"""Turning a scenario into a ready environment: apps seeded, events scheduled."""

from __future__ import annotations

from pare.apps.registry import CORE_APPS
from pare.env import EnvConfig, Environment
from pare.scenarios.model import Event, Scenario
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
    env.load({app: prepare_seed(app, data, scenario.start)[0] for app, data in scenario.seed.items()})
    for event in scenario.events:
        env.schedule(scheduled_event(event, scenario, env))
    env.scheduler.validate()
    return env


def scheduled_event(event: Event, scenario: Scenario, env: Environment) -> ScheduledEvent:
    """The kernel event for a scenario event."""
    app, _, tool = event.tool.partition("__")
    action = EventAction(app, tool, resolve_relative_times(event.args, scenario.start))
    return ScheduledEvent(event.id, _trigger(event, scenario, env), action)


def _trigger(event: Event, scenario: Scenario, env: Environment) -> Trigger:
    delay = parse_duration(event.delay)
    if event.at is not None:
        return AtTime(parse_time(event.at, scenario.start))
    if event.after is not None:
        return AfterEvent(event.after, delay)
    assert event.when is not None
    pattern = CompiledPattern.of(event.when, scenario.start)

    def condition(entry: LogEntry) -> bool:
        if not pattern.matches_call(entry):
            return False
        events = event_positions(env.log) if pattern.needs_event_positions else None
        return pattern.matches(entry, events)

    return WhenLogged(condition, delay, description=pattern.describe())
