"""The seed and the world's texts, read for what the mutant operators choose among: the people, the files,
the items of a kind and how alike two of them are, and the slots the world offers.

Pure functions of a scenario's data: :mod:`pare.scenarios.mutants` makes the mutants from what they find.
"""

from __future__ import annotations

import re
from collections.abc import Iterator, Mapping
from datetime import datetime
from typing import Any

from pare.apps.files import normalize_path
from pare.errors import ToolError
from pare.scenarios.timewords import mentions

_EMAIL = re.compile(r"[\w.+-]+@[\w-]+(?:\.[\w-]+)+")
_WORD = re.compile(r"[a-z0-9]+")
_SHORT_TEXT = 12
"""A text shorter than this offers no slot (an id, a name, a time field)."""


def people(seed: Mapping[str, Mapping[str, Any]]) -> list[frozenset[str]]:
    """The people of the seed, in three forms each a pool: email addresses, messaging user ids, and full
    names (of contacts and messaging users). The user is in none of them.
    """
    email = seed.get("email", {})
    own = {str(email.get("user_email", "")).lower()}
    addresses = {found for found in _EMAIL.findall(repr(seed)) if found.lower() not in own}
    messaging = seed.get("messaging", {})
    users = messaging.get("users", {}) if isinstance(messaging.get("users"), Mapping) else {}
    me = messaging.get("current_user_id")
    ids = {str(user) for user in users if user != me}
    names = {str(name) for user, name in users.items() if user != me}
    for contact in seed.get("contacts", {}).get("contacts", []) or []:
        if (
            isinstance(contact, Mapping)
            and contact.get("first_name")
            and contact.get("contact_id") != "contact-me"
        ):
            names.add(f"{contact['first_name']} {contact.get('last_name') or ''}".strip())
    return [frozenset(pool) for pool in (addresses, ids, names) if pool]


def files(seed: Mapping[str, Mapping[str, Any]]) -> dict[str, str]:
    """The seed's files: each normalised path with its content."""
    found = seed.get("files", {}).get("files", {})
    if not isinstance(found, Mapping):
        return {}
    return {
        normal_path(path): str(entry.get("content", "") if isinstance(entry, Mapping) else entry)
        for path, entry in found.items()
    }


def normal_path(path: str) -> str:
    """``path`` as the files app keeps it, or as written when the phone would refuse it."""
    try:
        return normalize_path(path)
    except ToolError:  # a path the phone would refuse is simply no seed file
        return path


def ids(data: Any, key: str) -> set[str]:
    """Every string under ``key`` anywhere in ``data``."""
    found: set[str] = set()
    if isinstance(data, Mapping):
        for name, item in data.items():
            if name == key and isinstance(item, str):
                found.add(item)
            else:
                found |= ids(item, key)
    elif isinstance(data, list):
        for item in data:
            found |= ids(item, key)
    return found


def places(data: Any, path: str = "") -> dict[str, set[str]]:
    """Each string in ``data`` with the places it is found at (paths, a list's items all at ``*``)."""
    found: dict[str, set[str]] = {}
    children: list[tuple[str, Any]] = []
    if isinstance(data, Mapping):
        children = [(f"{path}.{name}", item) for name, item in data.items()]
    elif isinstance(data, list):
        children = [(f"{path}[*]", item) for item in data]
    elif isinstance(data, str):
        found[data] = {path}
    for place, item in children:
        for text, where in places(item, place).items():
            found.setdefault(text, set()).update(where)
    return found


def record(data: Any, key: str, value: str) -> Mapping[str, Any] | None:
    """The item of ``data`` whose ``key`` is ``value`` (an event by its ``event_id``), or ``None``."""
    for found, _ in _records(data, key, value, ()):
        return found
    return None


def _records(
    data: Any, key: str, value: str, outer: tuple[Mapping[str, Any], ...]
) -> Iterator[tuple[Mapping[str, Any], tuple[Mapping[str, Any], ...]]]:
    """The items whose ``key`` is ``value``, each with the items it is kept in (a variant in its product)."""
    if isinstance(data, Mapping):
        if data.get(key) == value:
            yield data, outer
            return
        for item in data.values():
            yield from _records(item, key, value, (*outer, data))
    elif isinstance(data, list):
        for item in data:
            yield from _records(item, key, value, outer)


def description_words(data: Any, key: str, value: str) -> frozenset[str]:
    """The words that describe the item whose ``key`` is ``value``: its own texts and the plain texts of
    what it is kept in (a variant's size and its product's name), ids and numbers left out.
    """
    words: set[str] = set()
    for found, outer in _records(data, key, value, ()):
        for item in (found, *outer):
            for name, text in item.items():
                if isinstance(text, str) and not str(name).endswith("_id"):
                    words.update(_WORD.findall(text.lower()))
        break
    return frozenset(word for word in words if not word.isdigit())


def likeness(first: frozenset[str], second: frozenset[str]) -> float:
    """How alike two items' words are: the share of their words they have in common."""
    union = first | second
    return len(first & second) / len(union) if union else 0.0


def texts(data: Any) -> Iterator[str]:
    """Every text of ``data`` long enough to say something (a message, an email's body, a note)."""
    if isinstance(data, str):
        if len(data) >= _SHORT_TEXT:
            yield data
    elif isinstance(data, Mapping):
        for item in data.values():
            yield from texts(item)
    elif isinstance(data, list):
        for item in data:
            yield from texts(item)


def offered_slots(text: str, anchor: datetime) -> list[tuple[datetime, bool]]:
    """The moments a text offers, each with whether it has one reading only: each clock time it names with
    the day named last before it (or with it), so "Tuesday 14:00 or Thursday at 10am" offers both. A time
    named with no day before it is no slot (its day would be a guess); "at 6" gives both readings.
    """
    slots: list[tuple[datetime, bool]] = []
    day = None
    for mention in mentions(text, anchor.replace(tzinfo=None)):
        if len(mention.days) == 1:
            [day] = mention.days
        if day is None or not mention.times:
            continue
        for clock in sorted(mention.times):
            slots.append((datetime.combine(day, clock, tzinfo=anchor.tzinfo), len(mention.times) == 1))
    return slots


def offered_clocks(text: str, anchor: datetime) -> list[tuple[int, int]]:
    """The clock times a text names that have one reading only (``14:00``, ``9am``; not ``at 6``)."""
    return [
        (clock.hour, clock.minute)
        for mention in mentions(text, anchor.replace(tzinfo=None))
        if len(mention.times) == 1
        for clock in mention.times
    ]
