"""The people of a scenario's world named in free text, for the judge fallback's facts rule.

A wrong person is the commonest wrong detail a fallback written for the right words lets through: the
caption that thanks Ella and Sophie where the facts say Ella and Maya, the reminder that sends the
engineer's visit to Greg, the colleague's surname given to another. Times and amounts are read in any text,
but a name is only a detail where the reader knows it is one: the scenario's world lists its people (the
contacts, the messaging users, the phone's owner), so the names read are theirs, as written in the text:
a first or last name of three letters or more, capitalised, as a whole word. A name that is also a common
word ("May", "Will", "Bill", "Rose") is left out, since "May" may be the month and "Will" the verb.

A detail reads as ``("person", name)`` with the name lowercased, so "Maya" and "MAYA" are one. The facts
rule checks people only where the facts name one of them, and allows a person an allowed text names and the
phone's owner (a message signed with her own name states nothing about anyone else).
"""

from __future__ import annotations

import re
from collections.abc import Iterable, Iterator, Mapping
from dataclasses import dataclass
from typing import Any

from pare.scenarios.count_details import Found

_COMMON_WORDS = frozenset(("will", "bill", "mark", "rose", "grace", "hope", "dawn", "faith", "june",
                           "april", "august", "summer", "autumn", "amber", "ruby", "pearl", "iris",
                           "holly", "lily", "daisy", "heather", "hazel", "olive", "cliff", "dale",
                           "glen", "brook", "lane", "hill", "field", "wood", "stone", "ford", "bell",
                           "king", "page", "baker", "cook", "fisher", "green", "brown", "white",
                           "black", "gray", "grey", "young", "long", "short", "small", "little", "rich",
                           "hunter", "mason", "porter", "turner", "walker", "wells", "banks", "rivers",
                           "frank", "earnest", "chase", "drew", "grant", "lance", "nick", "sandy",
                           "sunny", "may", "art", "don", "guy", "ray", "pat", "sue", "jay", "eve",
                           "joy", "kit", "rob", "bob", "max", "sky"))  # fmt: skip
"""Names that are also everyday words, left out: the text may use the word, not the name."""
_NOT_A_PERSON = frozenset({"the", "a", "an"})
"""A first word that makes a contact a place or a business: "The Anchor" is a pub."""
_TITLES = frozenset({"dr", "mr", "mrs", "ms", "miss", "prof", "rev"})
"""Words before a name that are no name ("Dr Patel" is read as Patel)."""
_MIN_LENGTH = 3
"""Names of fewer letters are left out: "Jo", "Al" and "Ed" are too often part of another word."""


def known_names(seed: Mapping[str, Any]) -> frozenset[str]:
    """The first and last names of every person the ``seed`` lists (contacts, messaging users, the phone's
    owner), lowercased, without names shorter than three letters or that are also common words.
    """
    names: set[str] = set()
    for found in _people(seed):
        written = [word.strip(".,'\"()").lower() for word in found.split()]
        if written and written[0] in _NOT_A_PERSON:
            continue  # "The Anchor": a place kept as a contact
        names.update(
            name
            for name in written
            if len(name) >= _MIN_LENGTH and name.isalpha() and name not in _COMMON_WORDS | _TITLES
        )
    return frozenset(names)


def owner_names(seed: Mapping[str, Any]) -> frozenset[str]:
    """The names of the phone's owner, lowercased: the contact marked ``is_user`` and the messaging app's
    current user.
    """
    owner: set[str] = set()
    for app in seed.values():
        if not isinstance(app, Mapping):
            continue
        current = app.get("current_user_name")
        if isinstance(current, str):
            owner.update(current.lower().split())
        for contact in _records(app.get("contacts")):
            if contact.get("is_user"):
                owner.update(_full_name(contact).lower().split())
    return frozenset(owner)


def _people(seed: Mapping[str, Any]) -> Iterator[str]:
    """Every person's name the seed writes: contacts' first and last names, messaging users' names."""
    for app in seed.values():
        if not isinstance(app, Mapping):
            continue
        if isinstance(app.get("current_user_name"), str):
            yield app["current_user_name"]
        for contact in _records(app.get("contacts")):
            yield _full_name(contact)
        for user in _records(app.get("users")):
            if isinstance(user.get("name"), str):
                yield user["name"]


def _records(listed: object) -> Iterator[Mapping[str, Any]]:
    """The records of a seed collection, written as a list or as a mapping by id."""
    values = listed.values() if isinstance(listed, Mapping) else listed if isinstance(listed, list) else ()
    yield from (one for one in values if isinstance(one, Mapping))


def _full_name(contact: Mapping[str, Any]) -> str:
    return " ".join(str(contact.get(key) or "") for key in ("first_name", "last_name"))


@dataclass(frozen=True, slots=True)
class NameFinder:
    """Finds the names of one world in texts (compiled once per scenario)."""

    names: frozenset[str]
    pattern: re.Pattern[str] | None

    @classmethod
    def of(cls, names: Iterable[str]) -> NameFinder:
        """A finder of ``names`` (lowercased first or last names)."""
        kept = frozenset(names)
        if not kept:
            return cls(kept, None)
        alternatives = "|".join(sorted((re.escape(name) for name in kept), key=len, reverse=True))
        # capitalised as a name is ("Maya", "MAYA"), whole words only ("Mayan" is no Maya); a possessive
        # is the name ("Maya's")
        return cls(kept, re.compile(r"(?<![\w'-])(" + alternatives + r")(?![\w-])", re.IGNORECASE))

    def find(self, text: str) -> Iterator[Found]:
        """The names of the world ``text`` writes with a capital, in order."""
        if self.pattern is None:
            return
        for match in self.pattern.finditer(text):
            written = match.group(1)
            if written[0].isupper():
                yield Found(("person", written.lower()), written, *match.span())
