"""Who made each piece of app state: attribution from the actors' writes.

Success must be the assistant's work, not the user's. Every successful write by the user or the assistant
is diffed (the app data before and after the call), and each place in the state that the call created or
changed is marked with the actor and the action-log entry. Places are paths into the state snapshot,
with items of id-keyed mappings and of lists named by their identity (an item's ``*_id`` field, else its
value), so ``("calendar", "events", "ev-3")`` is one calendar event wherever it sits in a list.

Writes by the world (``env``: scheduled events, noise, wakeups) are not attributed: what the world
makes is like seed data, and an email arriving does not take credit from the assistant for work it did.

Credit is by field: :meth:`Attribution.written_by` says which of an item's fields an actor last set, so
a note the assistant appends to an event the user made by hand does not make the event's time the
assistant's work; :meth:`Attribution.hands` says who had a hand in an item at all, for limits on what an
actor may make.
"""

from __future__ import annotations

import json
from collections.abc import Iterable, Iterator, Mapping
from dataclasses import dataclass
from typing import Any

from pare.sim.log import Actor

StatePath = tuple[str, ...]

ATTRIBUTED_ACTORS: frozenset[Actor] = frozenset({"user", "assistant", "oracle"})
"""Actors whose writes are attributed (the oracle's too, for tests that drive it directly)."""

CONTROL_APPS: frozenset[str] = frozenset({"system", "agent_ui"})
"""Apps whose tools are the turn protocol, not app data: their writes are not attributed."""


@dataclass(frozen=True, slots=True)
class Mark:
    """Who made one place of the state: its creator (``None`` when it was seeded or made by the world)
    and its last changer among the attributed actors, with the log entries that did it.
    """

    created_by: Actor | None
    changed_by: Actor
    created_at: int | None
    """Log index of the call that created it, if an attributed actor did."""
    changed_at: int
    """Log index of the last attributed call that changed it."""

    def credits(self, actor: Actor) -> bool:
        """Whether ``actor`` made this: created it, or made its latest change."""
        return self.created_by == actor or self.changed_by == actor

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready form."""
        return {
            "created_by": self.created_by,
            "changed_by": self.changed_by,
            "created_at": self.created_at,
            "changed_at": self.changed_at,
        }


def item_key(item: Any) -> str:
    """The identity of a list item: its first ``*_id`` field when it is a record, else its value."""
    if isinstance(item, Mapping):
        for key, value in item.items():
            if str(key).endswith("_id") and isinstance(value, str | int):
                return str(value)
    if isinstance(item, str):
        return item
    return json.dumps(item, sort_keys=True, default=str)


def _keyed(value: Any) -> Mapping[str, Any] | None:
    if isinstance(value, Mapping):
        return value
    if isinstance(value, list):
        return {item_key(item): item for item in value}
    return None


def changed_places(before: Any, after: Any, path: StatePath = ()) -> Iterator[tuple[StatePath, bool]]:
    """The places where ``after`` differs from ``before``: ``(path, created)`` for the deepest changes."""
    old, new = _keyed(before), _keyed(after)
    if old is None or new is None:
        if before != after:
            yield path, False
        return
    for key, value in new.items():
        here = (*path, str(key))
        if key not in old:
            yield here, True
        elif old[key] != value:
            yield from changed_places(old[key], value, here)


def removed_places(before: Any, after: Any, path: StatePath = ()) -> Iterator[StatePath]:
    """The places ``before`` has and ``after`` no longer has (the outermost place of each removed part)."""
    old, new = _keyed(before), _keyed(after)
    if old is None or new is None:
        return
    for key, value in old.items():
        here = (*path, str(key))
        if key not in new:
            yield here
        elif new[key] != value:
            yield from removed_places(value, new[key], here)


class Attribution:
    """The marks of one episode, filled as actors write, and who removed what."""

    def __init__(self) -> None:
        self._marks: dict[StatePath, Mark] = {}
        self._hands: dict[StatePath, dict[Actor, int]] = {}
        """Per place, every actor that created or changed it (or something in it), with its latest call:
        the marks keep only the creator and the last changer."""
        self._removed: dict[StatePath, tuple[Actor, int]] = {}

    def record(self, actor: Actor, entry_index: int, app: str, before: Any, after: Any) -> None:
        """Mark what ``actor``'s call (log entry ``entry_index``) changed in ``app``'s data."""
        for place, created in changed_places(before, after, (app,)):
            self._mark(place, actor, entry_index, created)
            for depth in range(len(place) - 1, 0, -1):  # the item holding a changed field changed too
                self._mark(place[:depth], actor, entry_index, False)
        for place in removed_places(before, after, (app,)):
            self._removed[place] = (actor, entry_index)

    @classmethod
    def restored(
        cls,
        marks: Mapping[StatePath, Mark],
        hands: Mapping[StatePath, Mapping[Actor, int]],
        removed: Mapping[StatePath, tuple[Actor, int]],
    ) -> Attribution:
        """An episode's attribution as it was recorded (:meth:`marks`, :meth:`hands_of`, :meth:`removals`),
        to evaluate its checks again without playing it.
        """
        attribution = cls()
        attribution._marks = dict(marks)
        attribution._hands = {place: dict(actors) for place, actors in hands.items()}
        attribution._removed = dict(removed)
        return attribution

    def hands_of(self, place: StatePath) -> Mapping[Actor, int]:
        """Every actor that created or changed ``place`` (or anything in it), with its latest call, however
        long ago (:meth:`hands` keeps only those since what ``place`` holds now was made).
        """
        return self._hands.get(place, {})

    def removals(self) -> Mapping[StatePath, tuple[Actor, int]]:
        """Every place an attributed actor removed, with the last remover and its log entry (a place made
        again later stays listed: read it together with the final state).
        """
        return self._removed

    def marks(self) -> Mapping[StatePath, Mark]:
        """Every marked place (read only)."""
        return self._marks

    def _mark(self, place: StatePath, actor: Actor, index: int, created: bool) -> None:
        hands = self._hands.get(place)
        if hands is None:
            self._hands[place] = {actor: index}
        else:
            hands[actor] = index
        previous = self._marks.get(place)
        if created or previous is None:
            creator = actor if created else None
            self._marks[place] = Mark(creator, actor, index if created else None, index)
        else:
            self._marks[place] = Mark(previous.created_by, actor, previous.created_at, index)

    def mark(self, place: StatePath) -> Mark | None:
        """The mark of ``place``, or ``None`` when no attributed actor made or changed it."""
        return self._marks.get(place)

    def credits(self, place: StatePath, actors: frozenset[Actor]) -> bool:
        """Whether one of ``actors`` made ``place`` (created it, or made its latest change)."""
        found = self._marks.get(place)
        return found is not None and any(found.credits(actor) for actor in actors)

    def writer(self, place: StatePath) -> Actor | None:
        """The actor who last set what ``place`` holds: its latest change, unless it (or what holds it) was
        created since, by whom; ``None`` when no attributed actor set it (seeded, or made by the world).
        """
        since, creator = self._origin(place)
        own = self._marks.get(place)
        if own is not None and own.changed_at >= since:
            return own.changed_by
        return creator

    def written_by(self, item: StatePath, fields: Iterable[str], actors: frozenset[Actor]) -> frozenset[str]:
        """Those of ``fields`` of ``item`` that one of ``actors`` last set: by changing the field, or by
        creating the item (or what holds it) since. A field nobody set (seeded, or made by the world) is
        no one's; a field the item lacks is its creator's.
        """
        since, creator = self._origin(item)
        marks = self._marks
        found = []
        for name in fields:
            mark = marks.get((*item, name))
            who = mark.changed_by if mark is not None and mark.changed_at >= since else creator
            if who is not None and who in actors:
                found.append(name)
        return frozenset(found)

    def hands(self, place: StatePath) -> frozenset[Actor]:
        """Every actor that had a hand in what ``place`` holds now: created it (or what holds it, with it),
        or changed it or anything in it since. Wider than :meth:`credits`, which names only the creator
        and the last changer: what an actor may not make counts whatever came after it.
        """
        since, creator = self._origin(place)
        found = {actor for actor, index in self._hands.get(place, {}).items() if index >= since}
        if creator is not None:
            found.add(creator)
        return frozenset(found)

    def _origin(self, place: StatePath) -> tuple[int, Actor | None]:
        """When what ``place`` holds came to be, and by whom: the latest creation by an attributed actor of
        the place or of what holds it (``(-1, None)`` when it was seeded or made by the world). Changes
        before it were made to an earlier item of the same identity, since removed.
        """
        since: int = -1
        creator: Actor | None = None
        marks = self._marks
        for depth in range(len(place), 0, -1):
            mark = marks.get(place[:depth])
            if mark is not None and mark.created_at is not None and mark.created_at > since:
                since, creator = mark.created_at, mark.created_by
        return since, creator

    def to_dict(self) -> dict[str, dict[str, Any]]:
        """JSON-ready form, keyed by the dotted place."""
        return {".".join(place): mark.to_dict() for place, mark in sorted(self._marks.items())}


def place_of(state: Mapping[str, Any], dotted: str) -> StatePath | None:
    """The attribution place of a dotted state path (``shopping.orders.0`` names the order by its id)."""
    value: Any = state
    place: list[str] = []
    for part in dotted.split("."):
        if isinstance(value, Mapping) and part in value:
            value = value[part]
            place.append(part)
        elif isinstance(value, list) and part.isdigit() and int(part) < len(value):
            value = value[int(part)]
            place.append(item_key(value))
        else:
            return None
    return tuple(place)
