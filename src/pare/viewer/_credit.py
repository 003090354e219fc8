"""Who made each change of the state diff from start to end.

The trajectory's attribution marks each place of the apps' data that the user or the assistant created or
changed, by identity (an item of a list by its ``*_id``), with the log entry that did it. What the world
made (scheduled events, noise) carries no mark, nor what a read changed on the side (opening a
conversation marks it read), nor the turn protocol's apps (proposals, the assistant's messages). The
state diff names places by JSON Pointer, the items of a list by position. A change is credited to:

1. the mark of its own place (a list item by its identity), never a mark of a place above it: the
   conversation the assistant wrote in also holds the friend's reply, which the world made;
2. else the world's call that names the item (its id among the call's arguments or result): the first
   for an item that appeared, the last for a value that changed (for a field, the item holding it);
3. else, for a list item known only by its position, the mark of the list, or the last write that names
   the item holding the list (items moved up by a removal, which attribution does not mark);
4. else the other calls that name the item: the turn protocol's (a proposal is made by the assistant's
   message and answered by the user), and reads that changed it on the side. The world comes first:
   the user opening a conversation after a message arrived did not change when it was last updated;
5. else "the world", without a link (nothing, in the turn protocol's apps, which the world never writes).

A removed item is credited to the last call that names it (attribution keeps no mark of what is gone;
an item of a list known only by its position, to the last write that names the item holding the list).
An item that appeared is credited to who made it and, when someone changed it since, to them as well.
A field that the user or the assistant changed and the world changed again (when a conversation was last
updated) stays credited to the user or the assistant: the log does not say which fields a world call set.
"""

from __future__ import annotations

import re
from collections.abc import Iterable, Iterator, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

from pare.env.attribution import ATTRIBUTED_ACTORS, CONTROL_APPS, item_key
from pare.results.trajectory import LogRecord, PlaceRecord

WORLD = "the world"
_NAMES_DEPTH = 4
"""How deep into a call's arguments and result ids are looked for (ids sit near the top)."""


@dataclass(frozen=True)
class Credit:
    """Who made a change: an actor (or the world's event or noise) and, when known, the log entry."""

    who: str
    """``user``, ``assistant``, ``oracle``, ``event``, ``noise``, or :data:`WORLD`."""
    log_index: int | None
    event_id: str | None = None


@dataclass(frozen=True)
class _Call:
    index: int
    who: str
    event_id: str | None
    group: str
    """``world`` (env), ``attributed`` (a write of the user or assistant to app data, marked where it
    changed something), or ``other`` (reads, navigations, the turn protocol's apps)."""
    names: frozenset[str]


class Credits:
    """Credits the state diff's operations of one episode from its action log and attribution."""

    def __init__(self, log: Iterable[LogRecord], attribution: Mapping[str, PlaceRecord]) -> None:
        self._marks = attribution
        self._calls = [call for entry in log if (call := _call(entry)) is not None]
        self._by_index = {call.index: call for call in self._calls}

    def of(self, op: dict[str, Any]) -> list[Credit]:
        """Who made the operation ``op`` (RFC 6902), in the order they did: empty when unknown."""
        parts = pointer_parts(str(op.get("path", "")))
        if len(parts) < 2:
            return []
        kind = str(op.get("op", ""))
        positional = parts[-1].isdigit()
        own = parts[-1]
        if positional and kind in ("add", "replace") and "value" in op:
            own = item_key(op["value"])
        if kind == "remove":
            if positional:  # the list lost an item, known only by its position: who wrote to its holder
                return self._holder(parts, (("world", "attributed"),))
            return self._credits(self._last(own, ("world", "attributed", "other")))
        mark = self._mark([*parts[:-1], own]) or self._mark(parts)
        if kind == "add":
            found = self._appeared(parts, own, positional, mark)
        else:
            found = self._changed(parts, own, positional, mark)
        if not found and parts[0] not in CONTROL_APPS:  # the world never writes the turn protocol's apps
            return [Credit(WORLD, None)]
        return found

    def marked_under(self, dotted: str) -> list[int]:
        """The calls that created or changed ``dotted`` (a dotted place) or anything under it."""
        found: set[int] = set()
        for key, mark in self._marks.items():
            if key == dotted or key.startswith(dotted + "."):
                found.update(i for i in (mark.created_at, mark.changed_at) if i is not None)
        return sorted(found)

    def made(self, place: Sequence[str]) -> list[int]:
        """The calls that made ``place`` (an attribution place) and what it holds: the marks at and
        under it and, when no mark says who created it, the world's first call that names it.
        """
        dotted = ".".join(place)
        found = set(self.marked_under(dotted))
        own = self._marks.get(dotted)
        if len(place) > 1 and _index(own, "created_at") is None:
            world = self._first(place[-1], ("world",))
            if world is not None:
                found.add(world)
        return sorted(found)

    def _appeared(
        self, parts: list[str], own: str, positional: bool, mark: PlaceRecord | None
    ) -> list[Credit]:
        changed = _index(mark, "changed_at")
        if mark is not None and _index(mark, "created_at") is not None:
            return self._credits(_index(mark, "created_at"), changed)
        world = self._first(own, ("world",))
        if world is not None:
            return self._credits(world, changed)
        if changed is not None:
            return self._credits(changed)
        if positional and (listed := _index(self._mark(parts[:-1]), "changed_at")) is not None:
            return self._credits(listed)
        other = self._first(own, ("other",))
        if other is not None:
            return self._credits(other, self._last(own, ("other",)))
        return []

    def _changed(
        self, parts: list[str], own: str, positional: bool, mark: PlaceRecord | None
    ) -> list[Credit]:
        if (changed := _index(mark, "changed_at")) is not None:
            return self._credits(changed)
        if positional:
            world = self._last(own, ("world",))
            if world is not None:
                return self._credits(world)
            if (listed := _index(self._mark(parts[:-1]), "changed_at")) is not None:
                return self._credits(listed)
            # items moved up by a removal, which attribution does not mark: who wrote to the holder
            return self._holder(parts, (("world", "attributed"), ("other",)))
        return self._holder(parts, (("world",), ("other",)))

    def _holder(self, parts: list[str], groups: tuple[tuple[str, ...], ...]) -> list[Credit]:
        """The last call that names the innermost item holding ``parts`` (of the first of ``groups``
        that has one): a field changed as a whole item was written to.
        """
        holders = [holder for holder in reversed(parts[1:-1]) if not holder.isdigit()]
        for group in groups:
            for holder in holders:
                last = self._last(holder, group)
                if last is not None:
                    return self._credits(last)
        return []

    def _mark(self, place: list[str]) -> PlaceRecord | None:
        """The mark of ``place``; a list position inside it (an order's items, by position) stands for
        any item there, and the latest such mark is taken.
        """
        found = self._marks.get(".".join(place))
        inner = range(1, len(place) - 1)
        if found is not None or not any(place[i].isdigit() for i in inner):
            return found
        pattern = re.compile(
            r"\.".join(
                ".+" if i in inner and part.isdigit() else re.escape(part) for i, part in enumerate(place)
            )
        )
        matching = [mark for key, mark in self._marks.items() if pattern.fullmatch(key)]
        return max(matching, key=lambda mark: _index(mark, "changed_at") or -1, default=None)

    def _naming(self, name: str, groups: tuple[str, ...]) -> Iterator[_Call]:
        return (call for call in self._calls if call.group in groups and name in call.names)

    def _first(self, name: str, groups: tuple[str, ...]) -> int | None:
        return next((call.index for call in self._naming(name, groups)), None)

    def _last(self, name: str, groups: tuple[str, ...]) -> int | None:
        found = None
        for call in self._naming(name, groups):
            found = call.index
        return found

    def _credits(self, *indexes: int | None) -> list[Credit]:
        credits: list[Credit] = []
        for index in indexes:
            call = self._by_index.get(index) if index is not None else None
            if call is not None and all(credit.log_index != index for credit in credits):
                credits.append(Credit(call.who, call.index, call.event_id))
        return credits


def pointer_parts(pointer: str) -> list[str]:
    """The keys of a JSON Pointer (RFC 6901): ``/a~1b/0`` is ``["a/b", "0"]``."""
    return [part.replace("~1", "/").replace("~0", "~") for part in pointer.split("/")[1:]]


def _index(mark: PlaceRecord | None, key: str) -> int | None:
    if mark is None:
        return None
    return mark.created_at if key == "created_at" else mark.changed_at


def _call(entry: LogRecord) -> _Call | None:
    if not entry.ok:
        return None
    index, actor, app, kind, event_id = entry.index, entry.actor, entry.app, entry.kind, entry.event_id
    if actor == "env":
        group = "world"
        who = WORLD if event_id is None else ("noise" if event_id.startswith("noise-") else "event")
    else:
        writes_data = kind == "write" and app not in CONTROL_APPS
        group = "attributed" if writes_data and actor in ATTRIBUTED_ACTORS else "other"
        who = actor
    names: set[str] = set()
    _strings(entry.args, names, _NAMES_DEPTH)
    if kind in ("write", "env", "control"):  # what a write made is in its result; a read's lists everything
        _strings(entry.result, names, _NAMES_DEPTH)
    return _Call(index, who, event_id, group, frozenset(names))


def _strings(value: Any, into: set[str], depth: int) -> None:
    """Collect the strings in ``value`` (ids are strings; numbers would match list positions)."""
    if isinstance(value, str):
        into.add(value)
    elif depth > 0 and isinstance(value, dict):
        for item in value.values():
            _strings(item, into, depth - 1)
    elif depth > 0 and isinstance(value, list):
        for item in value:
            _strings(item, into, depth - 1)
