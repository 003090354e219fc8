"""Scheduled events and the scheduler that decides when each one fires.

An event is a tool call the world makes (an email arriving, a driver cancelling). It fires at an absolute
time, at a delay after the start, at a delay after another event completed, or at a delay after a condition
on the action log first holds ("after the assistant emails Bob, Bob replies 10 minutes later"). Dependents
fire whoever caused their trigger: a real run and an oracle run see the same world.
"""

from __future__ import annotations

import heapq
from collections.abc import Callable
from dataclasses import dataclass, field
from datetime import datetime, timedelta
from typing import Any

from pare.errors import UserInputError
from pare.sim.clock import ensure_utc
from pare.sim.log import LogEntry


@dataclass(frozen=True, slots=True)
class AtTime:
    """Fire at an absolute simulated time."""

    time: datetime


@dataclass(frozen=True, slots=True)
class AfterStart:
    """Fire ``delay`` after the start of the episode."""

    delay: timedelta = timedelta(0)


@dataclass(frozen=True, slots=True)
class AfterEvent:
    """Fire ``delay`` after the event ``event_id`` completed."""

    event_id: str
    delay: timedelta = timedelta(0)


@dataclass(frozen=True, slots=True)
class WhenLogged:
    """Fire ``delay`` after the first action-log entry for which ``condition`` holds.

    The condition may answer ``None``: it cannot tell yet (it waits for an answer asked elsewhere, such as
    a judge model's reading of the text). The scheduler then holds it on that entry until
    :meth:`EventScheduler.retest`.
    """

    condition: Callable[[LogEntry], bool | None]
    delay: timedelta = timedelta(0)
    description: str = "a condition on the action log"


Trigger = AtTime | AfterStart | AfterEvent | WhenLogged


@dataclass(frozen=True, slots=True)
class EventAction:
    """The call an event makes, as the ``env`` actor: ``app.tool(**args)``."""

    app: str
    tool: str
    args: dict[str, Any] = field(default_factory=dict)


@dataclass(frozen=True, slots=True)
class ScheduledEvent:
    """An event with its id, its trigger and the call it makes."""

    event_id: str
    trigger: Trigger
    action: EventAction
    withdrawn_by: str | None = None
    """An event whose log condition, met while this one is still due, withdraws it: a reactive event's
    ``otherwise`` (the counterpart's question back) is not sent once the rest of the answer has come."""


@dataclass(frozen=True, slots=True)
class DueEvent:
    """An event whose time has been resolved."""

    time: datetime
    event: ScheduledEvent


class EventScheduler:
    """Keeps events until they are due and releases them in a deterministic order.

    Order: by due time, then by the order in which they became scheduled (so two events at 09:05 fire in
    the order the scenario lists them).
    """

    def __init__(self, start: datetime) -> None:
        self.start = ensure_utc(start)
        self._events: dict[str, ScheduledEvent] = {}
        self._heap: list[tuple[datetime, int, str]] = []
        self._sequence = 0
        self._dependents: dict[str, list[ScheduledEvent]] = {}
        self._conditions: list[ScheduledEvent] = []
        self._log_cursor = 0
        self.completed: dict[str, datetime] = {}
        """Completed events and when they completed."""
        self.set_off: dict[str, int] = {}
        """Events waiting on a log condition that it set off, each with the index of the log entry that
        did (the action a reactive event answers); set off before it is due, so also for one still due."""
        self._held: dict[str, list[LogEntry]] = {}
        """Events whose condition could not tell yet on an entry, each with that entry and every entry
        observed since, to be tested in order by :meth:`retest`."""
        self.withdrawn: dict[str, str] = {}
        """Events withdrawn before they were due (see :attr:`ScheduledEvent.withdrawn_by`), each with the
        event that withdrew it."""

    def add(self, event: ScheduledEvent) -> None:
        """Schedule ``event``. An ``AfterEvent`` may name an event added later; :meth:`validate` checks."""
        if event.event_id in self._events:
            raise UserInputError(f"two events share the id '{event.event_id}'")
        self._events[event.event_id] = event
        trigger = event.trigger
        if isinstance(trigger, AtTime):
            self._push(ensure_utc(trigger.time), event.event_id)
        elif isinstance(trigger, AfterStart):
            self._push(self.start + trigger.delay, event.event_id)
        elif isinstance(trigger, AfterEvent):
            if trigger.event_id in self.completed:
                self._push(self.completed[trigger.event_id] + trigger.delay, event.event_id)
            else:
                self._dependents.setdefault(trigger.event_id, []).append(event)
        else:
            self._conditions.append(event)

    def validate(self) -> None:
        """Check that every ``AfterEvent`` names a known event and that no dependency forms a cycle."""
        problems: list[str] = []
        for event in self._events.values():
            trigger = event.trigger
            if isinstance(trigger, AfterEvent) and trigger.event_id not in self._events:
                problems.append(f"event '{event.event_id}' waits for unknown event '{trigger.event_id}'")
        for event_id in self._events:
            seen: list[str] = []
            current: str | None = event_id
            while current is not None and current in self._events:
                if current in seen:
                    cycle = " -> ".join([*seen[seen.index(current) :], current])
                    problems.append(f"events depend on each other in a cycle: {cycle}")
                    break
                seen.append(current)
                parent = self._events[current].trigger
                current = parent.event_id if isinstance(parent, AfterEvent) else None
        if problems:
            raise UserInputError("; ".join(sorted(set(problems))))

    def _push(self, time: datetime, event_id: str) -> None:
        heapq.heappush(self._heap, (time, self._sequence, event_id))
        self._sequence += 1

    def observe(self, entries: list[LogEntry]) -> None:
        """Check waiting conditions against new log entries; each fires at most once."""
        if not self._conditions:
            self._log_cursor += len(entries)
            return
        for entry in entries:
            fired = []
            for event in self._conditions:
                held = self._held.get(event.event_id)
                if held is not None:  # tested in order: not on this entry before the one it waits on
                    held.append(entry)
                    continue
                holds = _when_logged(event).condition(entry)
                if holds is None:
                    self._held[event.event_id] = [entry]
                elif holds:
                    fired.append(event)
            for event in fired:
                self._set_off(event, entry)
        self._log_cursor += len(entries)

    def _set_off(self, event: ScheduledEvent, entry: LogEntry) -> None:
        self._conditions.remove(event)
        self.set_off[event.event_id] = entry.index
        self._push(entry.time + _when_logged(event).delay, event.event_id)
        self._withdraw_for(event.event_id)

    def _withdraw_for(self, event_id: str) -> None:
        """Take out of the schedule the events due later that ``event_id``'s being set off withdraws."""
        kept = []
        for item in self._heap:
            waiting = self._events[item[2]]
            if waiting.withdrawn_by == event_id:
                self.withdrawn[waiting.event_id] = event_id
            else:
                kept.append(item)
        if len(kept) != len(self._heap):
            self._heap = kept
            heapq.heapify(self._heap)

    @property
    def undecided(self) -> bool:
        """Whether a condition waits for an answer before it can tell whether an entry meets it."""
        return bool(self._held)

    def retest(self) -> None:
        """Test each held condition again on the entries it was held on, in order, once the answers it
        waited for are in: it sets its event off on the first entry that meets it, or is held again where
        it still cannot tell. Call it before the clock moves, so a reaction is due when it would have been.
        """
        held, self._held = self._held, {}
        for event in [event for event in self._conditions if event.event_id in held]:
            entries = held[event.event_id]
            for position, entry in enumerate(entries):
                holds = _when_logged(event).condition(entry)
                if holds is None:
                    self._held[event.event_id] = entries[position:]
                    break
                if holds:
                    self._set_off(event, entry)
                    break

    @property
    def log_cursor(self) -> int:
        """How many log entries :meth:`observe` has seen."""
        return self._log_cursor

    def next_time(self) -> datetime | None:
        """When the next scheduled event is due, or ``None`` when nothing is scheduled."""
        return self._heap[0][0] if self._heap else None

    def pop_due(self, now: datetime) -> DueEvent | None:
        """Remove and return the earliest event due at or before ``now``."""
        if self._heap and self._heap[0][0] <= now:
            time, _, event_id = heapq.heappop(self._heap)
            return DueEvent(time, self._events[event_id])
        return None

    def is_reaction(self, event_id: str) -> bool:
        """Whether ``event_id`` was set in motion by something logged: its log condition held, or it
        waits on an event (at any remove) whose condition held.
        """
        current: str | None = event_id
        while current is not None:
            if current in self.set_off:
                return True
            trigger = self._events[current].trigger
            current = trigger.event_id if isinstance(trigger, AfterEvent) else None
        return False

    def scheduled_reactions(self) -> list[str]:
        """Reactions set in motion and not yet fired, in the order they are due."""
        return [event_id for _, _, event_id in sorted(self._heap) if self.is_reaction(event_id)]

    def pop_reaction(self, until: datetime) -> DueEvent | None:
        """Remove and return the earliest reaction due at or before ``until``, passing over every other
        event (those stay scheduled).
        """
        for item in sorted(self._heap):
            time, _, event_id = item
            if time > until:
                return None
            if self.is_reaction(event_id):
                self._heap.remove(item)
                heapq.heapify(self._heap)
                return DueEvent(time, self._events[event_id])
        return None

    def complete(self, event_id: str, at: datetime) -> None:
        """Record that ``event_id`` completed at ``at`` and schedule the events waiting for it."""
        self.completed[event_id] = at
        for dependent in self._dependents.pop(event_id, []):
            assert isinstance(dependent.trigger, AfterEvent)
            self._push(at + dependent.trigger.delay, dependent.event_id)

    @property
    def waiting_on_conditions(self) -> list[str]:
        """Ids of events still waiting for their log condition."""
        return [e.event_id for e in self._conditions]

    @property
    def pending(self) -> int:
        """Events not yet fired (nor withdrawn): scheduled, waiting on another event, or on a condition."""
        return len(self._heap) + sum(len(v) for v in self._dependents.values()) + len(self._conditions)


def _when_logged(event: ScheduledEvent) -> WhenLogged:
    trigger = event.trigger
    assert isinstance(trigger, WhenLogged)
    return trigger
