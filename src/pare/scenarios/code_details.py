"""Codes and streets in free text, for the judge fallback's facts rule.

A reply that quotes the wrong order number or sends someone to the wrong street passes a fallback written
for the right words beside them. Two more kinds of detail are read here:

* ``code``: an identifier: a word mixing letters and digits ("HX-20931", "4A", "DW-7040"), a postcode
  ("SW1A 1AA", one code however spaced), a
  number of five to eight digits ("12008453"), or a number after "#" or "no." of three or more digits.
  Compared without case, spaces, dashes or "#": "hx 20931" is "HX-20931".
* ``street``: a street or road named with its kind ("Pell Street", "12 Pell Street", "Mill Lane 5"),
  compared by name and, where both give one, house number: "21 Pell Street" is not "12 Pell Street",
  and "Abbot Street" is not "Abbey Road". A name that ends with the other is the same street ("Saved
  Willow Row" at the start of a sentence is Willow Row).

Times, dates, amounts, counts and phone numbers are read first and are never codes ("7pm", "4th",
"2-bed").
"""

from __future__ import annotations

import re
from collections.abc import Iterable

from pare.scenarios.count_details import Found

_STREET_KINDS = (r"Road|Rd|Way|Street|St|Lane|Ln|Close|Avenue|Ave|Drive|Dr|Place|Pl|Court|Terrace|Gardens|"
                 r"Crescent|Square|Sq|Row|Hill|Park|Grove|Mews|Walk|Parade|Quay|Wharf|Boulevard|"
                 r"Embankment|Yard|Green|Rise|Vale")  # fmt: skip
_STREET = re.compile(
    r"(?<![\w:.])(?:(?P<number>\d{1,4}[A-Za-z]?)\s+)?"
    r"(?P<name>(?:[A-Z][a-z']+\s+){1,3}(?:" + _STREET_KINDS + r"))\b\.?"
    r"(?:\s+(?P<after>\d{1,4}[A-Za-z]?)\b(?![:.]\d))?"
)
"""A street: "12 Pell Street", "Pell Street", "Mill Lane 5" (the number after, as written abroad)."""
_STREET_SHORT = {"rd": "road", "st": "street", "ln": "lane", "ave": "avenue", "dr": "drive", "pl": "place",
                 "sq": "square"}  # fmt: skip
_NOT_NAME = frozenset({"The", "On", "At", "In", "To", "From", "Via", "And", "Or", "Near", "Off", "By"})

_CODE = re.compile(
    r"(?<![\w#-])(?:(?P<postcode>[A-Z]{1,2}\d[A-Z\d]?\s\d[A-Z]{2})(?![\w-])"
    r"|#\s?(?P<hashed>\d{3,})"
    r"|(?:no\.?|number)\s?(?P<numbered>\d{3,})"
    r"|(?P<mixed>(?=[\w-]*\d)(?=[\w-]*[A-Za-z])[A-Za-z0-9]+(?:-[A-Za-z0-9]+)*)"
    r"|(?<![\d.,])(?P<long>\d{5,8}))(?![\w-])(?![.,]\d)",
    re.I,
)
_NOT_CODE = re.compile(
    r"^(?:\d+(?:st|nd|rd|th|am|pm|h\d*|hrs?|mins?|k|m|x|s|kg|g|ml|l|km|cm|mm|p|gb|mb|yrs?|wks?|pc|pcs|"
    r"mph|kmh|in|ft|a\.?m|p\.?m)|\d{1,2}h\d{2}|x\d+|\d+-(?:year|month|week|day|hour|minute|min|bed|"
    r"bedroom|night|person|people|seat|door|piece)s?(?:-old)?|(?:mid|late|early)-\d+s?|covid-19|"
    r"q[1-4]|h[12]|[1-9]d|3d|4k|\d+-\d+)$",
    re.I,
)
"""Words with letters and digits that are no identifier: ordinals, times, units, "2-bed", "Q3"."""


def _key(code: str) -> str:
    return re.sub(r"[\s#-]", "", code).upper()


def codes(text: str) -> Iterable[Found]:
    """Every identifier of ``text`` (already masked where other details were read)."""
    for match in _CODE.finditer(text):
        written = next(group for group in match.groups() if group)
        if match.group("mixed") and _NOT_CODE.match(written):
            continue
        yield Found(("code", _key(written)), match.group(0), *match.span())


def _street_name(name: str) -> str:
    words = name.split()
    while len(words) > 2 and words[0] in _NOT_NAME:
        words = words[1:]
    kind = words[-1].lower().rstrip(".")
    words[-1] = _STREET_SHORT.get(kind, kind)
    return " ".join(word.lower() for word in words)


def streets(text: str) -> Iterable[Found]:
    """Every street of ``text``, as ``("street", (name, number))`` (number ``""`` when none is given)."""
    for match in _STREET.finditer(text):
        name = match.group("name")
        if name.split()[0] in _NOT_NAME and len(name.split()) == 2:
            continue  # "The Street", "On Road" are no street names
        number = (match.group("number") or match.group("after") or "").upper()
        yield Found(("street", (_street_name(name), number)), match.group(0).strip(), *match.span())


def same_street(one: str, other: str) -> bool:
    """Whether two street names (as :func:`streets` reads them) name one street: equal, or one ends with
    the other (a capitalised word before the name, "Saved Willow Row", is no part of it).
    """
    return one == other or one.endswith(" " + other) or other.endswith(" " + one)


def same_code(one: str, other: str) -> bool:
    """Whether two codes (as :func:`codes` keys them) are one: equal, or the shorter, of 4 or more
    characters, ends or begins the other ("20931" of "HX-20931" written "HX 20931").
    """
    short, long = sorted((one, other), key=len)
    return short == long or (len(short) >= 4 and (long.endswith(short) or long.startswith(short)))
