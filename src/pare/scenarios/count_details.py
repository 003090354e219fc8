"""Counts and parts of the day in free text, for the judge fallback's facts rule.

A wrong detail that is neither a clock time, a date nor an amount slips past a fallback written for the
right words: "size twelve" for a size 11, "the fourth floor" for the third, "one bedroom" for a two-bed,
"Sunday afternoon" for a Sunday-morning trip. Two more kinds of detail are read here:

* ``count``: a number tied to what it counts or labels, as ``(label, value)``. The label comes before the
  number ("size 12", "platform 3", "room 204", "table for 4") or after it ("4th floor", "two-bed",
  "three nights", "2 tickets"). Numbers may be written in words or as ordinals; words are read by the
  ``text2num`` library. Labels are kept singular and a few synonyms are one label (bed and bedroom; people,
  persons and guests). The facts rule checks a count only when the facts give a count of the same label,
  so "15 minutes" in a reply is read only where the facts count minutes.
* ``part_of_day``: "morning", "afternoon", "evening", "tonight", "lunchtime", "first thing". Such a word
  is allowed when an allowed text names it or gives a time inside it; "this morning" and "tonight" are
  also allowed when the text is sent in that part of the day (they then say when it is written).
"""

from __future__ import annotations

import re
from collections.abc import Iterable
from dataclasses import dataclass
from datetime import time
from functools import lru_cache

from text_to_num import alpha2digit

_UNITS = ("zero|one|two|three|four|five|six|seven|eight|nine|ten|eleven|twelve|thirteen|fourteen|fifteen|"
          "sixteen|seventeen|eighteen|nineteen")  # fmt: skip
_TENS = "twenty|thirty|forty|fifty|sixty|seventy|eighty|ninety"
_ORDINALS = ("first|second|third|fourth|fifth|sixth|seventh|eighth|ninth|tenth|eleventh|twelfth|thirteenth|"
             "fourteenth|fifteenth|sixteenth|seventeenth|eighteenth|nineteenth|twentieth")  # fmt: skip
_NUMBER = (
    r"(?P<number>\d{1,4}(?:\.5|st|nd|rd|th)?"
    rf"|(?:half\s+a\s+)?dozen|(?:(?:{_TENS})(?:[\s-](?:{_UNITS}|{_ORDINALS}))?|{_UNITS}|{_ORDINALS}))"
)
"""A number as digits (with an ordinal's ending), in words ("twenty-one", "fourth") or as a dozen."""
_BELOW_HUNDRED = rf"(?:(?:{_TENS})(?:[\s-](?:{_UNITS}))?|{_UNITS})"
NUMBER_IN_WORDS = (
    rf"(?:(?:a|{_BELOW_HUNDRED})\s+thousand(?:\s+(?:and\s+)?)?)?"
    rf"(?:(?:a|{_UNITS})\s+hundred(?:\s+(?:and\s+)?)?)?{_BELOW_HUNDRED}"
    rf"|(?:a|{_BELOW_HUNDRED})\s+(?:thousand|hundred)"
)
"""A whole number in words, up to the thousands ("ninety-six", "two hundred and forty", "a thousand")."""


def words_value(written: str) -> int | None:
    """The value of a whole number in words (see :data:`NUMBER_IN_WORDS`), read by ``text2num``."""
    words = " ".join(written.lower().replace("-", " ").split())
    if words.startswith("a "):
        words = "one " + words[2:]
    digits = alpha2digit(words, "en", threshold=0).strip()
    return int(digits) if digits.isdigit() else None


_BEFORE = (r"size|platform|gate|room|table\s+for|seat|row|unit|bay|locker|level|terminal|floor|pitch|"
           r"court|aisle|door|flat|apartment|house|stall|stand|desk|car|coach|carriage|berth|cabin|"
           r"box")  # fmt: skip
"""Labels written before their number ("size 12", "table for 4")."""
_AFTER = (r"floors?|bed(?:room)?s?|people|persons?|guests?|adults?|children|kids?|nights?|tickets?|seats?|"
          r"rooms?|boxes|box|bags?|packs?|bottles?|items?|pairs?|copies|copy|sessions?|classes|class|lessons?|"
          r"weeks?|days?|months?|years?|hours?|minutes?|mins?|tablets?|doses?|payslips?|pages?|photos?|"
          r"invoices?|parcels?|packages?|cakes?|pizzas?|dozen|eggs?|cups?|slices?|portions?|loaves|loaf|"
          r"cases?|crates?|sacks?|rolls?|units|spaces?|places?|spots?|stops?|stations?")  # fmt: skip
"""Labels written after their number ("4th floor", "three nights", "2 tickets")."""

_LABEL_FIRST = re.compile(
    rf"(?<![\w-])(?P<label>{_BEFORE})\s*(?:no\.?\s*|number\s+|#\s*|is\s+|:\s*|of\s+)?{_NUMBER}"
    r"\b(?![.:,]\d)(?!\s*(?:am|pm)\b)",
    re.I,
)
_NUMBER_FIRST = re.compile(
    rf"(?<![\w.,:£$€#/-])(?:(?P<first>{_NUMBER.replace('?P<number>', '')})\s*(?:-|\u2013|to|or)\s*)?{_NUMBER}"
    rf"(?:\s*-\s*|\s+)(?:of\s+(?:the\s+|those\s+|these\s+)?)?(?P<label>{_AFTER})\b(?!-)",
    re.I,
)
"""A count whose label follows its number; a range ("20-25 minutes", "two or three nights") gives both."""

_SAME_LABEL = {
    "bed": "bedroom", "person": "people", "persons": "people", "guest": "people", "table for": "people",
    "kid": "child", "children": "child", "min": "minute", "loaves": "loaf", "boxes": "box",
    "classes": "class", "copies": "copy",
}  # fmt: skip
_ENDINGS = re.compile(r"(?:st|nd|rd|th)$", re.I)


@dataclass(frozen=True, slots=True)
class Found:
    """One count, part of the day, code or street: its reading, how the verdict shows it, and where it is."""

    reading: tuple[str, object]
    shown: str
    start: int
    end: int
    also: tuple[str, object] | None = None
    """The other end of a range of counts."""

    @property
    def readings(self) -> frozenset[tuple[str, object]]:
        """What it may mean: its reading, and the other end of a range."""
        return frozenset({self.reading} if self.also is None else {self.reading, self.also})


DURATIONS = frozenset({"minute", "hour", "day", "week", "month", "year", "night"})
"""Labels of lengths of time: facts that give one of them make every one of them checked ("two months"
is a wrong detail where the facts say two years)."""


def _label(written: str) -> str:
    label = " ".join(written.lower().split())
    if label in _SAME_LABEL:
        return _SAME_LABEL[label]
    if label.endswith("s") and not label.endswith("ss") and label not in ("people",):
        label = label[:-1]
    return _SAME_LABEL.get(label, label)


@lru_cache(maxsize=1024)
def _value(number: str) -> str | None:
    """The value of a number as written, as digits: "12", "4th", "twelve", "twenty-one", "fourth", "a
    dozen", and a half size ("9.5").
    """
    written = " ".join(number.lower().replace("-", " ").split())
    if written == "dozen":
        return "12"
    if written == "half a dozen":
        return "6"
    digits = written if written[0].isdigit() else alpha2digit(written, "en", threshold=0)
    digits = _ENDINGS.sub("", digits.strip())
    return str(int(digits)) if digits.isdigit() else digits if re.fullmatch(r"\d+\.5", digits) else None


_ORDINAL_WORD = re.compile(rf"\d(?:st|nd|rd|th)\b|\b(?:{_ORDINALS})\b", re.I)


def ordinal(found: Found) -> bool:
    """Whether ``found`` counts with an ordinal ("4th floor", "the fourth floor"), which a date reader would
    take for a day of the month.
    """
    return bool(re.search(rf"\d(?:st|nd|rd|th)\b|\b(?:{_ORDINALS})\b", found.shown, re.I))


_NOT_COUNTED = frozenset(
    ("of", "and", "or", "to", "the", "a", "an", "in", "at", "on", "for", "from", "by", "with", "past", "till",
     "until", "before", "after", "am", "pm", "percent", "per", "more", "less", "each", "times", "time",
     "pound", "dollar", "euro", "pence", "cent", "quid", "buck", "since", "ago", "later", "earlier",
     "instead", "back", "away", "today", "tomorrow", "tonight", "then", "now", "left", "over", "under",
     "about", "than")
)  # fmt: skip
_ANY_NOUN = re.compile(rf"(?<![\w.,:£$€#/-]){_NUMBER}\s+(?P<label>[a-z][a-z'-]{{2,}})\b")
"""Any other count: a number under 100 and the lower-case word after it ("10 slides", "three
cartridges"), read for the labels a check's facts count; a word of :data:`_NOT_COUNTED` is no label."""


def counts(text: str) -> Iterable[Found]:
    """Every count of ``text``, as ``("count", (label, value))`` readings: of the labels listed here,
    and of any word after a number (:data:`_ANY_NOUN`).
    """
    seen: set[int] = set()
    for pattern in (_LABEL_FIRST, _NUMBER_FIRST, _ANY_NOUN):
        for match in pattern.finditer(text):
            if match.start() in seen:
                continue
            value = _value(match.group("number"))
            if value is None:
                continue
            label = _label(match.group("label"))
            if pattern is _ANY_NOUN and (
                match.group("label") in _NOT_COUNTED or label in _NOT_COUNTED or len(value) > 2
            ):
                continue  # a word that counts nothing; "305 cartridge" names a model, it counts none
            seen.add(match.start())
            shown = " ".join(match.group(0).split())
            if label in DURATIONS and _ORDINAL_WORD.search(match.group("number")):
                continue  # "the first weeks", "the second day": a place in time, no length of it
            first = match.groupdict().get("first")
            other = _value(first) if first else None
            if other is not None:  # a range: either end will do
                yield Found(("count", (label, other)), shown, *match.span(), also=("count", (label, value)))
            else:
                yield Found(("count", (label, value)), shown, *match.span())


_PARTS = {
    "morning": ((time(4), time(12)),),
    "afternoon": ((time(12), time(18)),),
    "evening": ((time(17), time(23, 59)),),
    "tonight": ((time(17), time(23, 59)), (time(0), time(3))),
    "lunchtime": ((time(11, 30), time(14, 30)),),
}
_PART = re.compile(
    r"\b(?P<this>this\s+)?(?P<part>morning|afternoon|evening|tonight|lunch\s?time|first\s+thing)\b", re.I
)


def _part_name(written: str) -> str:
    name = "".join(written.lower().split())
    return "morning" if name == "firstthing" else name


def parts_of_day(text: str) -> Iterable[Found]:
    """Every part of the day ``text`` names, as ``("part", name)`` readings ("this morning" and "tonight"
    are told by :func:`says_now`: the part the text is sent in will do for them).
    """
    for match in _PART.finditer(text):
        yield Found(("part", _part_name(match.group("part"))), match.group(0), *match.span())


def says_now(text: str, start: int) -> bool:
    """Whether the part of the day at ``start`` of ``text`` is said of the day it is sent ("this
    morning", "tonight").
    """
    match = _PART.match(text, start)
    return match is not None and (match.group("this") is not None or match.group("part").lower() == "tonight")


def within(part: str, moment: time) -> bool:
    """Whether ``moment`` is in the part of the day named ``part``."""
    return any(first <= moment <= last for first, last in _PARTS.get(part, ()))
