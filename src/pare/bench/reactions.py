"""What the world did in a self-test run: the scenario's events that fired, and for a reactive event which
branch it took, the reply for the right question or the ``otherwise`` correction.

The gate reads it to hold a correct solution to the world's answer: a run that must succeed and does, while
the world answered it with a correction ("Sorry, which day?"), shows either a weak trigger (an unrelated
action set the reaction off) or a world that does not recognise a right answer, unless the variant says why
the correction is part of the solution (``otherwise_ok``).
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass
from datetime import datetime
from typing import Literal

from pare.env import Environment
from pare.scenarios.matchers import compile_matcher
from pare.scenarios.model import Event, Scenario
from pare.scenarios.stats import FREE_TEXT_FIELDS

Branch = Literal["timed", "reply", "otherwise"]


@dataclass(frozen=True, slots=True)
class WorldEvent:
    """One of the scenario's events that fired in a run, or was set off and still due when it ended."""

    event: str
    """The scenario event's id (for an ``otherwise`` branch, the reactive event it belongs to)."""
    branch: Branch
    """``timed`` (``at`` or ``after``), or for a reactive event ``reply`` (its own call: the action met
    ``if_args``, or it has none) or ``otherwise`` (the correction for an action that did not)."""
    at: datetime | None
    """When it fired; ``None`` when it was set off but the run ended before it was due."""
    fired_id: str
    """The id it fired under: the event's, or its ``otherwise`` reaction's."""
    text: str = ""
    """What the world said (the call's free-text arguments), for a reader of the run."""
    cause: str = ""
    """For a reactive event: the action that set it off (``#6 assistant messaging.send_message``)."""
    cause_text: str = ""
    """What that action said."""

    def describe(self, start: datetime) -> str:
        """``09:12 practice_confirms (otherwise: "Sorry, which slot?")``, the day relative to ``start``."""
        when = _clock(self.at, start) if self.at is not None else "due after the end"
        branch = "" if self.branch == "timed" else f" ({self.branch}"
        if branch and self.text:
            branch += f': "{_short(self.text)}"'
        if branch and self.cause:
            branch += f", after {self.cause}"
        return f"{when} {self.event}{branch}{')' if branch else ''}"


def world_events(scenario: Scenario, env: Environment) -> tuple[WorldEvent, ...]:
    """The scenario's events that fired in the run played in ``env`` (or were set off), in time order."""
    scheduler = env.scheduler
    fired = scheduler.completed
    found: list[WorldEvent] = []
    for event in scenario.events:
        if event.when is None:
            if event.id in fired:
                found.append(WorldEvent(event.id, "timed", fired[event.id], event.id, _text(event.args)))
            continue
        branches: list[tuple[Branch, str | None, dict[str, object]]] = [("reply", event.id, event.args)]
        if event.otherwise is not None:
            branches.append(("otherwise", event.otherwise_id, event.otherwise.args))
        for branch, fired_id, args in branches:
            if fired_id is None or fired_id not in scheduler.set_off or fired_id in scheduler.withdrawn:
                continue  # an otherwise withdrawn before it was due: the rest of the answer came in time
            entry = env.log[scheduler.set_off[fired_id]]
            cause = f"#{entry.index} {entry.actor} {entry.app}.{entry.tool}"
            at = fired.get(fired_id)
            found.append(WorldEvent(event.id, branch, at, fired_id, _text(args), cause, _text(entry.args)))
    order = {event.id: index for index, event in enumerate(scenario.events)}
    return tuple(
        sorted(found, key=lambda e: (e.at is None, e.at or scenario.start, order[e.event], e.branch))
    )


def corrected_solution(
    scenario: Scenario, run: str, events: tuple[WorldEvent, ...], excused: frozenset[str] = frozenset()
) -> Iterator[str]:
    """Why a run that must succeed and did is still wrong: the world answered it with an ``otherwise``
    branch (one not in ``excused``, the events a variant's ``otherwise_ok`` names).
    """
    by_id = {event.id: event for event in scenario.events}
    for world in events:
        if world.branch != "otherwise" or world.event in excused:
            continue
        event = by_id[world.event]
        said = f' ("{_short(world.text)}")' if world.text else ""
        written = f' "{_short(world.cause_text)}"' if world.cause_text else ""
        cause = f"{world.cause}{written}, which does not meet its if_args ({_wanted(event)})"
        if run == "oracle":
            yield (
                f"the world answered the oracle with the otherwise branch of event '{world.event}'{said}, "
                f"set off by {cause}: the oracle must ask what the world answers, and the event's 'when' "
                "match only that"
            )
        else:
            name = run.removeprefix("variant:")
            yield (
                f"variant '{name}' passed, but the world answered it with the otherwise branch of event "
                f"'{world.event}'{said}, set off by {cause}: a correct solution must get the reply, not the "
                "correction. Narrow the event's 'when' if that action is unrelated, widen its if_args if it "
                "is right, make the variant expect: fail if it is wrong, or give the variant otherwise_ok: "
                f"{{{world.event}: <why the correction is part of this solution>}}"
            )


def unused_excuses(run: str, excused: frozenset[str], events: tuple[WorldEvent, ...]) -> Iterator[str]:
    """A variant's ``otherwise_ok`` entries that its run never needed: stale declarations."""
    corrected = {world.event for world in events if world.branch == "otherwise"}
    for event_id in sorted(excused - corrected):
        yield (
            f"{run} declares otherwise_ok for event '{event_id}', but the world never answered it with that "
            "event's otherwise branch: drop the entry"
        )


def _wanted(event: Event) -> str:
    return _short(
        ", ".join(f"{name}: {compile_matcher(raw).describe()}" for name, raw in event.if_args.items()), 120
    )


_SAID = ("content", "body", "text", "message")
"""The arguments that carry what was said, before subjects and titles."""


def _text(args: dict[str, object]) -> str:
    """What a world call says: its message, else its other free text (a subject, a title)."""
    said = next((str(args[key]) for key in _SAID if args.get(key)), "")
    return said or " ".join(str(value) for key, value in args.items() if key in FREE_TEXT_FIELDS and value)


def _short(text: str, width: int = 50) -> str:
    flat = " ".join(text.split())
    return flat if len(flat) <= width else flat[: width - 1].rstrip() + "…"


def _clock(at: datetime, start: datetime) -> str:
    at = at.astimezone(start.tzinfo)
    days = (at.date() - start.date()).days
    return f"day{days:+d} {at:%H:%M}" if days else f"{at:%H:%M}"
