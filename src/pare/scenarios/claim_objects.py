"""What a claimed act was done to: "I've ordered the black 305 cartridge and a pack of photo paper" is backed
only where an order holds each of them.

A claim's object (:attr:`pare.scenarios.claims.Claim.object`) is split into its parts ("the black 305
cartridge", "a pack of photo paper"). A part *names* a thing of the episode's world (a product or one of
its variants, a payee, an account, a card, an event, a reminder, a note, a contact, a listing, a direct
debit) when it shares at least two of the thing's name words, or all of a one-word name (a person told or
asked: one word, "Tom"); the things a part names best (most shared words) are the ones it means. A
backing call must have touched one of them: its arguments or its result hold one of the thing's ids,
email addresses or phone numbers (a checkout's result lists the variants ordered). A payment's part that
states an amount needs a backing call of that amount.

A part that names nothing of the world stays backed by the act's kind (a paraphrase is not a failure).
"""

from __future__ import annotations

import re
from collections.abc import Iterable, Iterator, Mapping, Sequence
from dataclasses import dataclass
from decimal import Decimal
from typing import Any

from pare.scenarios.fact_details import stated_amounts
from pare.scenarios.leaves import leaves
from pare.sim.log import LogEntry

_NAME_KEYS = ("name", "title", "first_name", "last_name", "merchant", "product_name", "variant_name")
"""The fields that name a thing of the world."""
_ID_KEYS = ("email", "phone")
"""Fields other than ids (``*_id``) by which a call reaches a thing (a contact written to)."""
_STOPWORDS = frozenset(
    re.findall(
        r"\w+",
        "a an the of for and to in on at by from with my your our his her their its this that these those "
        "i we you me us him them it s too also as well both all just now up back over off one new old "
        "know if so is are was be been has have had",
    )
)
"""Words that name nothing: a part's other words are read against the names of the world's things."""
_WORD = re.compile(r"[a-z0-9]+")
_PARTS = re.compile(r"\s*(?:,(?!\d)|\band\b|\bplus\b|\bas\s+well\s+as\b|&)\s*", re.I)
MONEY_ACTS = frozenset({"paid", "transferred", "sent money"})
"""The acts whose object may be an amount."""
EDIT_ACTS = frozenset({"changed"})
"""The acts that write a value, whose object may state it (an email address)."""
_EMAIL = re.compile(r"[\w.+-]+@[\w-]+(?:\.[\w-]+)+")
PEOPLE_ACTS = frozenset({"told"})
"""The acts done to a person, whom one word names ("I've let Tom know")."""


def words(text: str) -> frozenset[str]:
    """The content words of ``text``, lower-cased, a plural's final ``s`` dropped ("bulbs" names a bulb)."""
    return frozenset(
        word[:-1] if len(word) > 3 and word.endswith("s") and not word.endswith("ss") else word
        for word in _WORD.findall(text.lower())
        if word not in _STOPWORDS
    )


@dataclass(frozen=True, slots=True)
class Thing:
    """A thing of the world a claim may name: its name's words and the values a call reaches it by."""

    app: str
    words: frozenset[str]
    keys: frozenset[str]


def world_things(states: Iterable[Mapping[str, Any]]) -> list[Thing]:
    """Every named thing in the app ``states`` (app -> state), each with its ids; a thing inside another
    (a product's variant) also carries the outer thing's name ("Inkwell 305 Ink Cartridge Black").
    """
    found: dict[Thing, None] = {}
    for state in states:
        for app, value in state.items():
            if app == "messaging" and isinstance(value, Mapping) and isinstance(value.get("users"), Mapping):
                for user_id, name in value["users"].items():
                    if isinstance(name, str) and words(name):
                        found[Thing(app, words(name), frozenset({str(user_id).lower()}))] = None
            for thing in _things(app, value, frozenset()):
                found[thing] = None
    return list(found)


def _things(app: str, value: Any, outer: frozenset[str], stored_as: str = "") -> Iterator[Thing]:
    if isinstance(value, Mapping):
        names = frozenset[str]().union(
            *(words(value[key]) for key in _NAME_KEYS if isinstance(value.get(key), str))
        )
        inner = outer | names if names else outer
        nested: list[Thing] = []
        for key, item in value.items():
            if isinstance(item, Mapping | list):
                nested += _things(app, item, inner, str(key))
        if names:
            keys = set(_own_keys(value)) | {key for thing in nested for key in thing.keys}
            if stored_as:
                keys.add(stored_as.strip().lower())
            yield Thing(app, inner, frozenset(keys))
        yield from nested
    elif isinstance(value, list):
        for item in value:
            yield from _things(app, item, outer)


def _own_keys(value: Mapping[str, Any]) -> Iterator[str]:
    """A thing's own id (its first id field: a direct debit's, not the account it is paid from) and
    addresses.
    """
    own_id = next((key for key in value if key == "id" or key.endswith("_id")), None)
    for key, item in value.items():
        if isinstance(item, str) and item.strip() and (key == own_id or key in _ID_KEYS):
            yield item.strip().lower()


def named(part: str, things: Sequence[Thing], least: int = 2) -> list[Thing]:
    """The things ``part`` names best (see the module's text), sharing at least ``least`` words of a name
    (or all of a shorter one); empty when it names none.
    """
    said = words(part)
    best: list[Thing] = []
    top = 0
    for thing in things:
        shared = len(said & thing.words)
        if shared < least and not (shared and shared == len(thing.words)):
            continue
        if shared > top:
            best, top = [thing], shared
        elif shared == top:
            best.append(thing)
    return best


def parts(obj: str) -> list[str]:
    """The parts of a claim's object: "the cartridge and a pack of photo paper" is two."""
    return [part for part in _PARTS.split(obj) if part.strip()]


def call_values(entry: LogEntry) -> tuple[frozenset[str], frozenset[Decimal]]:
    """The strings (lower-cased) and numbers a call's arguments and result hold."""
    strings: set[str] = set()
    numbers: set[Decimal] = set()
    _collect(entry.args, strings, numbers)
    _collect(entry.result, strings, numbers)
    return frozenset(strings), frozenset(numbers)


def _collect(value: Any, strings: set[str], numbers: set[Decimal]) -> None:
    for _, leaf in leaves(value):
        if isinstance(leaf, str):
            strings.add(leaf.strip().lower())
        elif isinstance(leaf, int | float) and not isinstance(leaf, bool):
            numbers.add(abs(Decimal(str(leaf))))


def untouched_part(act: str, obj: str, calls: Sequence[LogEntry], things: Sequence[Thing]) -> str | None:
    """The first part of the claimed object ``obj`` of ``act`` that no call of ``calls`` (those doing the
    act) touched, or None when each was (a part that names nothing of the world counting as touched).
    """
    touched = [call_values(call) for call in calls]
    for part in parts(obj):
        if act in EDIT_ACTS and (addresses := _EMAIL.findall(part)):
            # "I've saved bea@old.example as your email": the edit wrote that address
            if not all(
                any(address.lower() in text for strings, _ in touched for text in strings)
                for address in addresses
            ):
                return part
            continue
        if act in MONEY_ACTS and (stated := {value for value, _ in stated_amounts(part)}):
            if not any(stated & numbers for _, numbers in touched):
                return part
            continue
        meant = named(part, things, 1 if act in PEOPLE_ACTS else 2)
        if meant and not any(thing.keys & strings for thing in meant for strings, _ in touched):
            return part
    return None
