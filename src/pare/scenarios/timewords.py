"""The days and clock times named in free text, read as dates and times.

Checks such as ``mentions_time: day+3 09:30`` must accept "Thursday at 9:30", "half nine on the 2nd" and
"9.30 in the morning on Thursday" alike. Two readers share the work, and a text's mentions are the union of
what they find (a stretch of text read by the first is not read again by the second):

* **Rules for the forms people write most** (this module's patterns). They give every reading of an
  ambiguous form, which a single parse cannot: "at 6" is 06:00 or 18:00, "next Thursday" the coming one or
  the one after, "20/03" either order. They also cover what the library reads wrongly or not at all:

  - a weekday is the next such day *on or after* the reference day (the library skips today); "last
    Saturday" (or "this past Saturday") is the latest one *before* it, "yesterday" and "last night" the
    day before;
  - "the 2nd" is the next 2nd on or after the reference day: said on 5 June it is 2 July, said on
    1 June it is 2 June (the library picks a fixed month); "the 5th of this month" (of next, of last
    month) is that month's; in words too ("Saturday the tenth", "the twenty-first of May"; not "the
    first time");
  - "half nine" is 09:30 or 21:30 (British usage: half past nine), "quarter past 3", "ten to four",
    "20 past 3", "nine o'clock", "at nine";
  - "8 in the evening", "8 tonight", "9 in the morning", "11 at night": the part of the day picks the
    reading of the hour;
  - ranges name both ends: "2-4pm" (14:00 and 16:00), "11-1pm" (11:00 and 13:00), "between 2 and 4",
    "from 9:30 to 11", "14:00-16:00";
  - prices are not times ("$18.15"), and a three-letter weekday counts only with a capital ("Sat").

* **dateparser** (``dateparser.search.search_dates``, then its parser for what each found phrase names)
  for the rest: relative phrases ("in two days", "in 3 days at 5pm", "2 days from now", "in an hour",
  "in two weeks") and a month before "the" and its day ("June the 2nd"). Its search also proposes false
  dates ("we" as Wednesday, "may" as May, a lone "22" as the 22nd, "a month" after a price, "an hour" in
  "it takes half an hour"), so only a phrase without a comma, with a number, that counts from now ("in
  ...", "... from now", "... ago"; "... later" counts from another moment) or names a month and "the" day
  is taken from it; it gives a day only
  where the phrase names one, and a time only where the rules read none. Only a text with such a count or
  month form is given to it at all.

Texts are read relative to a reference moment (when the text was sent where the check knows it, else the
scenario's start: :func:`pare.scenarios.matchers.written_at`), in that moment's time zone: the phone's
zone, UTC in this release. dateparser is imported on the first text that needs it (never by
``pare --help`` or a run whose checks read no days or times), and each text's reading is remembered.
"""

from __future__ import annotations

import re
from collections.abc import Callable, Iterable, Iterator
from dataclasses import dataclass
from datetime import date, datetime, time, timedelta
from functools import lru_cache
from typing import Any

_WEEKDAYS = ("monday", "tuesday", "wednesday", "thursday", "friday", "saturday", "sunday")
_WEEKDAY_ABBREVIATIONS = {"Mon": 0, "Tue": 1, "Tues": 1, "Wed": 2, "Thu": 3, "Thur": 3, "Thurs": 3, "Fri": 4,
                          "Sat": 5, "Sun": 6}  # fmt: skip
_MONTHS = ("january", "february", "march", "april", "may", "june", "july", "august", "september", "october",
           "november", "december")  # fmt: skip
_MONTH_WORD = (
    r"(jan(?:uary)?|feb(?:ruary)?|mar(?:ch)?|apr(?:il)?|may|june?|july?|aug(?:ust)?|sept?(?:ember)?|"
    r"oct(?:ober)?|nov(?:ember)?|dec(?:ember)?)\.?"
)
_ORDINAL = r"(\d{1,2})(?:st|nd|rd|th)?"
_HOUR_NAMES = ("one", "two", "three", "four", "five", "six", "seven", "eight", "nine", "ten", "eleven",
               "twelve")  # fmt: skip
_HOUR_WORDS = {word: number for number, word in enumerate(_HOUR_NAMES, start=1)}
_HOUR = r"(\d{1,2}|" + "|".join(_HOUR_WORDS) + r")"
"""An hour as digits or as a word ("nine")."""
_MINUTE_WORDS = {"five": 5, "ten": 10, "quarter": 15, "a quarter": 15, "twenty": 20, "twenty five": 25,
                 "twenty-five": 25, "half": 30}  # fmt: skip
_WORD_END = r"(?![^\W\d_])"
_WORD_START = r"(?<![^\W\d_])"
_NOT_A_PRICE = r"(?<![\d$£€.:])"

_FULL_WEEKDAY = re.compile(
    _WORD_START
    + r"(next\s+|this\s+past\s+|this\s+|last\s+|past\s+)?("
    + "|".join(_WEEKDAYS)
    + r")"
    + _WORD_END,
    re.I,
)
_SHORT_WEEKDAY = re.compile(_WORD_START + r"(" + "|".join(_WEEKDAY_ABBREVIATIONS) + r")" + _WORD_END + r"\.?")
_RELATIVE_DAY = re.compile(
    _WORD_START
    + r"(the\s+day\s+after\s+tomorrow|the\s+day\s+before\s+yesterday|tomorrow|tmrw|tmw|2moro|tomoz|yesterday|"
    + r"last\s+night|today|"
    + r"tonight|this\s+(?:morning|afternoon|evening))"
    + _WORD_END,
    re.I,
)
_RELATIVE_OFFSETS = {"the day after tomorrow": 2, "tomorrow": 1, "tmrw": 1, "tmw": 1, "2moro": 1, "tomoz": 1,
                     "yesterday": -1, "last night": -1,
                     "the day before yesterday": -2}  # fmt: skip
"""Days from the reference day that each relative word names (the others name that day itself)."""
_DAY_MONTH = re.compile(
    r"(?<!\d)" + _ORDINAL + r"(?:\s+of)?\s+" + _MONTH_WORD + _WORD_END + r"(?:\s+(\d{4}))?", re.I
)
_MONTH_DAY = re.compile(_MONTH_WORD + r"\s+" + _ORDINAL + r"(?![\d:])(?:,?\s+(\d{4}))?", re.I)
_COUNTED_BY_ORDINAL = (
    r"(?!\s+(?:floor|storey|story|time|times|place|row|class|edition|birthday|anniversary|year|grade|"
    r"attempt|round|generation|series|season|book|chapter|century|avenue|street|person|people|item|one|"
    r"in\s+line|choice|option|stop|flat|house|door|gate|platform|bedroom|pair|week|day|month)\b)"
)
"""What an ordinal counts when it is no day of the month: "the 4th floor", "her 30th birthday"."""
_THE_NTH = re.compile(
    _WORD_START
    + r"the\s+(\d{1,2})(?:st|nd|rd|th)"
    + _WORD_END
    + _COUNTED_BY_ORDINAL
    + r"(?:\s+of\s+(this|next|last)\s+month)?",
    re.I,
)
""""the 2nd" and "the 5th of this month" (or of next or last month, which say the month)."""
_ISO_DATE = re.compile(r"(?<!\d)(\d{4})-(\d{2})-(\d{2})(?!\d)")
_DAY_SPAN = re.compile(
    r"(?<![\d:.,£$€])" + _ORDINAL + r"\s*(?:-|\u2013|\u2014|to|until|till|through|and|&)\s*"
    r"(?:(?:"
    + "|".join((*_WEEKDAYS, *_WEEKDAY_ABBREVIATIONS))
    + r")\.?,?\s+)?(?:the\s+)?("
    + _ORDINAL
    + r"(?:\s+of)?\s+"
    + _MONTH_WORD
    + _WORD_END
    + r"(?:\s+(\d{4}))?)",
    re.I,
)
""""Friday 12 to Sunday 14 September", "3-5 June": the first day takes the month written after the second."""
_DAY_AFTER = re.compile(
    r"(?:\band|\bor|\bto|\bthrough|&|,)\s+the\s+day\s+after"
    + _WORD_END
    + r"(?!\s+(?:tomorrow|that|this|the|next|her|his|their|my|your|our)\b)",
    re.I,
)
""""closed tomorrow and the day after": the day after the day just named."""
_END_OF_MONTH = re.compile(
    _WORD_START + r"(?:the\s+)?end\s+of\s+(?:(the|this|next)\s+month|" + _MONTH_WORD + r")" + _WORD_END, re.I
)
""""by the end of the month", "end of next month", "the end of June": the month's last week."""
_NEXT_WEEK_NEAR = re.compile(r"^(?:\s+[\w']+){0,3}?\s+next\s+week\b|\bnext\s+week[\s,]+(?:on\s+)?$", re.I)
""""Tuesday next week", "my Tuesday run next week", "next week, Tuesday": a weekday of next week."""
_SLASH_DATE = re.compile(r"(?<![\d/])(\d{1,2})/(\d{1,2})(?:/(\d{2,4}))?(?![\d/])")
_DOTTED_DATE = re.compile(r"(?<![\d.])(\d{1,2})\.(\d{1,2})\.(\d{4}|\d{2})(?!\d|\.\d)")
"""A date with dots and its year ("21.05.2026", at a sentence's end too), not a version ("1.2.3.4")."""
""""5.7.2025" (day, month, year: with a year, so a time such as "5.30" is never read as a date)."""

_SUFFIX = r"(a\.?m\.?|p\.?m\.?)" + _WORD_END
_COUNTED = (
    r"\s+(?!(?:am|pm|a\.m|p\.m|o'clock|on|at|in|this|tomorrow|today|tonight|next|works?|is|suits?|would|should|"
    r"could|that|then|please|if|for|or|and|but|so|ok|okay|fine|sharp|latest|the|to|with|instead|thanks|thank|"
    r"see|cheers|as|we|i|you|anyway|anyhow|though|too|also|maybe|probably|hopefully|earliest|ish|yeah|yes|"
    r"tomorrow|sat|sun|mon|tue|wed|thu|fri|now|again|instead|slots?|appointments?|bookings?|trains?|bus|"
    r"meetings?|sessions?|class|call|viewing|showing|shows?|performance|film|screening|flight|ferry|match|"
    r"game|service|one|option|start|kick-?off|from|outside|near|by|"
    r"downstairs|upstairs|opposite|behind|round|before|after|until|till|via|when|where|pick-?up|arrival|"
    r"cab|taxi|ride|car|coach|drop-?off|departure|reservation|table|slot)\b)[a-z]"
)
"""A word after a number that says the number counts something ("between 2 and 4 guests", "at one point"),
so it is not an hour."""
_ENDPOINT = r"(\d{1,2})(?:[:.](\d{2}))?(?:\s?" + _SUFFIX + r")?"
"""One end of a range of clock times: "2", "2pm", "9:30", "9.30am"."""
_DASH_RANGE = re.compile(
    _NOT_A_PRICE
    + _ENDPOINT
    + r"\s*(?:[-\u2013\u2014]|to|until|till)\s*"
    + _ENDPOINT
    + r"(?![\d:.]|[x\u00d7])",
    re.I,
)
""""2-4pm", "9:30 to 11", "14:00-16:00": read only when one end has am/pm or minutes (a bare "2-4" may be a
score or a count)."""
_WORDED_RANGE = re.compile(
    _WORD_START
    + r"(?:between\s+"
    + _ENDPOINT
    + r"\s+and|from\s+"
    + _ENDPOINT
    + r"\s+(?:to|until|till|-))\s+"
    + _ENDPOINT
    + r"(?![\d:.])(?!"
    + _COUNTED
    + ")",
    re.I,
)
""""between 2 and 4", "from 2 to 4pm": bare hours are read here, unless a word counts them ("between 2 and 4
guests")."""
_PAST_TO = re.compile(
    _WORD_START + r"(a\s+quarter|quarter|half|twenty[\s-]five|twenty|ten|five|\d{1,2}\s+minutes|\d{1,2})\s+"
    r"(past|after|to)\s+" + _HOUR + _WORD_END + r"(?![:.]\d)",
    re.I,
)
""""quarter past 3", "half past nine", "ten to four", "20 past 3", "25 minutes to 4"."""
_PAST_TO_NAMED = re.compile(
    _WORD_START + r"(a\s+quarter|quarter|half|twenty[\s-]five|twenty|ten|five|\d{1,2}\s+minutes|\d{1,2})\s+"
    r"(past|after|to)\s+(midnight|noon|midday)" + _WORD_END,
    re.I,
)
""""five to midnight" (23:55), "quarter past noon" (12:15)."""
_HALF_HOUR = re.compile(
    _WORD_START + r"half\s+" + _HOUR + _WORD_END + r"(?![:.]\d|\s+(?:an?\s+)?(?:hours?|days?))", re.I
)
""""half nine": half past nine, as said in Britain."""
_CLOCK = re.compile(_NOT_A_PRICE + r"(\d{1,2})(?:\s?[:.]\s?|h)(\d{2})(?!\d)(?:\s?" + _SUFFIX + r")?", re.I)
"""A clock time: "18:15", "6.15 pm", "18h15" (the "h" between the digits, so "26x26x5 H13" is no time)."""
_HOUR_SUFFIX = re.compile(
    _NOT_A_PRICE + _WORD_START + _HOUR + r"\s?(a\.?m\.?|p\.?m\.?|o'clock)" + _WORD_END, re.I
)
_STREET = (
    r"(?-i:(?:\s+[A-Z][\w'-]*){1,3}\s+(?:Road|Rd|Street|St|Lane|Ln|Avenue|Ave|Way|Close|Court|Ct|Drive|Dr|"
    r"Terrace|Terr|Place|Pl|Gardens|Row|Walk|Grove|Crescent|Square|Sq|Hill|Park|Mews|Yard|Parade|Quay|Wharf)\b)"
)
"""A street name after a number, capitalised ("at 14 Larch Road" is an address, not two o'clock; "at 3 on
the way home" is a time)."""
_AT_HOUR = re.compile(
    _WORD_START
    + r"(?:at|from|by|around|until|till)\s+"
    + _HOUR
    + r"(?:\s+(fifteen|thirty|forty[\s-]?five))?(?![\d:%]|[.,]\d|\s?(?:am|pm|a\.m|p\.m))"
    + _WORD_END
    + r"(?!"
    + _STREET
    + r")",
    re.I,
)
_COUNTED_AFTER = re.compile(_COUNTED, re.I)
_PERIOD = (
    r"\s*(?:o'clock\s*)?(?:in\s+the\s+(morning|afternoon|evening)|at\s+(night)|to(night)|"
    r"(?:this|tomorrow|[a-z]+day)\s+(morning|afternoon|evening|night))" + _WORD_END
)
_PERIOD_AFTER = re.compile(_PERIOD, re.I)
_PERIOD_BEFORE = re.compile(
    _WORD_START
    + r"(morning|afternoon|evening|eve|tonight|night)[\s,]+(?:(?:at|about|around|from|say|by|maybe|roughly|"
    r"approximately|approx\.?|ish|usual|the\s+usual|-|\u2013)[\s,]+){0,2}$",
    re.I,
)
"""The part of the day said just before a time ("this evening at 7", "Friday morning, about half nine"):
it picks the time's reading where the time alone has two."""
"""The part of the day said after a time ("8 in the evening"): it picks the time's reading."""
_HOUR_BEFORE_PERIOD = re.compile(
    _NOT_A_PRICE + _WORD_START + _HOUR + r"(?:[:.](\d{2}))?(?=" + _PERIOD + ")", re.I
)
""""8 in the evening", "nine tonight": an hour read as one only because a part of the day follows."""
_WORD_CLOCK = re.compile(
    _WORD_START
    + r"("
    + "|".join(_HOUR_WORDS)
    + r")\s+(fifteen|thirty|forty[\s-]?five)"
    + _WORD_END
    + r"(?![\s-]+(?:minutes?|mins?|years?|pounds?|quid|dollars?|euros?|people|guests|of)\b)",
    re.I,
)
""""ten thirty", "six fifteen", "seven forty-five": an hour and its minutes in words (not "ten thirty-minute
slots" or "six fifteen-year-olds")."""
_NAMED_TIME = re.compile(_WORD_START + r"(noon|midday|midnight)" + _WORD_END, re.I)

_WEEKDAY_TO_DATE = re.compile(r"[\s,.]*(?:the\s+)?", re.I)
"""What may stand between a weekday and the date it is written with."""
_DAY_WORDS = (
    r"days?|weeks?|fortnight|today|tomorrow|tonight|"
    + "|".join(_WEEKDAYS)
    + "|"
    + _MONTH_WORD.removesuffix(r"\.?")
)
_LIBRARY_DAY = re.compile(_WORD_START + r"(?:" + _DAY_WORDS + r")" + _WORD_END, re.I)
"""A word that names a day: only a phrase with one gives a day ("8 in the evening" names no day)."""
_UNIT = r"(?:minutes?|hours?|days?|weeks?|fortnight)"
_COUNT = r"(?:an?|a\s+few|\d+|" + "|".join(_HOUR_WORDS) + r")"
_LIBRARY_CUE = re.compile(
    _WORD_START
    + r"(?:(?:in|within)\s+(?!an?\s+minute\b)"  # "in a minute" is soon, not a clock time
    + _COUNT
    + r"\s+"
    + _UNIT
    + r"|(?<!half\s)"  # "half an hour ago" is no hour ago
    + _COUNT
    + r"\s+"
    + _UNIT
    + r"\s+(?:from\s+(?:now|today|tomorrow)|ago)|"
    + _MONTH_WORD
    + r"\s+the\s+\d)"
    + _WORD_END,
    re.I,
)
"""What the library reads and the rules do not: a count of units from now ("in two days", "3 days from
now", "in an hour", but not "in a minute", which says soon) or a month before "the" and its day ("June the
2nd"). Only a text with one is given to it, and only the stretch around it. "A week later" is not read: it
counts from another moment than now ("the course starts a week later, Saturday the tenth")."""
_RELATIVE_PHRASE = re.compile(
    r"^(?:in|within)\s|"
    + _WORD_START
    + r"(?:from\s+(?:now|today|tomorrow)|ago)"
    + _WORD_END
    + "|"
    + _MONTH_WORD
    + r"\s+the\s+\d",
    re.I,
)
"""A phrase the library's reading is taken from: a moment counted from now ("in two days", "2 days from now";
"it takes half an hour" is a duration), or a month before "the" and its day."""
_NUMBER = re.compile(r"\d|" + _WORD_START + r"(?:an?|" + "|".join(_HOUR_WORDS) + r")" + _WORD_END, re.I)


@dataclass(frozen=True, slots=True)
class Mention:
    """A day or a clock time named in a text: every reading of it (``6:15`` is 06:15 or 18:15)."""

    start: int
    days: frozenset[date] = frozenset()
    times: frozenset[time] = frozenset()


def _hour_number(word: str) -> int:
    return int(word) if word.isdigit() else _HOUR_WORDS[word.lower()]


def _clock_readings(hour: int, minute: int, suffix: str | None) -> frozenset[time]:
    if minute > 59 or hour > 24:
        return frozenset()
    suffix = (suffix or "").replace(".", "").lower()
    if suffix in ("am", "pm"):
        if not 1 <= hour <= 12:
            return frozenset()
        base = hour % 12
        return frozenset({time(base + (12 if suffix == "pm" else 0), minute)})
    hour %= 24
    if 1 <= hour <= 12:  # no am/pm: read it both ways (people write "at 6" for 18:00)
        return frozenset({time(hour % 12, minute), time(hour % 12 + 12, minute)})
    return frozenset({time(hour, minute)})


def _in_period(readings: frozenset[time], period: str) -> frozenset[time]:
    """The readings that fall in the part of the day ``period`` ("evening"); all of them if none does."""
    keep: Callable[[time], bool]
    if period == "morning":
        keep = lambda moment: 4 <= moment.hour < 12  # noqa: E731
    elif period == "night":
        keep = lambda moment: moment.hour >= 18 or moment.hour < 4  # noqa: E731
    else:
        keep = lambda moment: moment.hour >= 12  # noqa: E731
    return frozenset(filter(keep, readings)) or readings


def _range_readings(
    first: tuple[str, str | None, str | None], last: tuple[str, str | None, str | None]
) -> tuple[frozenset[time], frozenset[time]]:
    """Both ends of a range; an end without am/pm takes the other's, or the other half of the day where
    that would put it after the other end ("11-1pm" is 11:00 to 13:00, "2-4pm" 14:00 to 16:00).
    """
    (hour1, minute1, suffix1), (hour2, minute2, suffix2) = first, last
    h1, m1, h2, m2 = int(hour1), int(minute1 or 0), int(hour2), int(minute2 or 0)
    if suffix2 and not suffix1 and h1 <= 12:
        ends = _clock_readings(h2, m2, suffix2)
        starts = _clock_readings(h1, m1, suffix2)
        if ends and starts and min(starts) > min(ends):
            starts = _clock_readings(h1, m1, "am" if suffix2.lower().startswith("p") else "pm")
        return starts, ends
    if suffix1 and not suffix2 and h2 <= 12:
        starts = _clock_readings(h1, m1, suffix1)
        ends = _clock_readings(h2, m2, suffix1)
        if ends and starts and min(ends) < min(starts):
            ends = _clock_readings(h2, m2, "am" if suffix1.lower().startswith("p") else "pm")
        return starts, ends
    return _clock_readings(h1, m1, suffix1), _clock_readings(h2, m2, suffix2)


def _month_number(word: str) -> int:
    prefix = word.lower().rstrip(".")[:3]
    return next(index for index, name in enumerate(_MONTHS, start=1) if name.startswith(prefix))


def _safe_date(year: int, month: int, day: int) -> date | None:
    try:
        return date(year, month, day)
    except ValueError:
        return None


def _year_readings(anchor: date, month: int, day: int, year: str | None) -> frozenset[date]:
    if year:
        number = int(year) + (2000 if len(year) == 2 else 0)
        found = _safe_date(number, month, day)
        return frozenset({found}) if found else frozenset()
    return frozenset(
        d for d in (_safe_date(anchor.year, month, day), _safe_date(anchor.year + 1, month, day)) if d
    )


def _weekday_readings(anchor: date, weekday: int, qualifier: str) -> frozenset[date]:
    said = " ".join(qualifier.lower().split())
    if said in ("last", "past", "this past"):  # "last Saturday": the latest one before today
        return frozenset({anchor - timedelta(days=(anchor.weekday() - weekday - 1) % 7 + 1)})
    first = anchor + timedelta(days=(weekday - anchor.weekday()) % 7)
    if said == "next":  # "next Thursday": this coming one or the one after
        return frozenset({first, first + timedelta(days=7)})
    return frozenset({first})


_MONTH_IN = re.compile(_WORD_START + _MONTH_WORD + _WORD_END, re.I)
_DIGIT_DATE = re.compile(r"\d[/.-]\d")
"""A date written with its month: in words ("16 June") or in digits ("16/06", "2025-06-16")."""
_BARE_NTH = re.compile(r"(?<![\w/.:])(\d{1,2})(?:st|nd|rd|th)" + _WORD_END, re.I)
_AFTER_WEEKDAY = re.compile(
    r"(?:" + "|".join(_WEEKDAYS) + "|" + "|".join(_WEEKDAY_ABBREVIATIONS) + r")\.?,?\s+$", re.I
)
"""A weekday just before a bare ordinal: "Sunday 19th" dates the 19th as "Sunday the 19th" does."""
_SENTENCE_END = re.compile(r"[!?\n]|\.(?=\s|$)")
"""Where a sentence ends, for a bare "the 5th" that takes its month from a date before it."""


def _nth_of_month(today: date, day: int, which: str) -> date | None:
    """``day`` of this month, of next month or of last month ("the 5th of last month")."""
    month_start = today.replace(day=1)
    if which == "next":
        month_start = (month_start + timedelta(days=32)).replace(day=1)
    elif which == "last":
        month_start = (month_start - timedelta(days=1)).replace(day=1)
    return _safe_date(month_start.year, month_start.month, day)


def _next_nth(today: date, day: int) -> date | None:
    """The next ``day`` of a month on or after ``today``: this month's, or the following month's."""
    month_start = today.replace(day=1)
    for _ in range(3):  # the 31st may skip a month that lacks it
        found = _safe_date(month_start.year, month_start.month, day)
        if found is not None and found >= today:
            return found
        month_start = (month_start + timedelta(days=32)).replace(day=1)
    return None


def _last_nth(today: date, day: int) -> date | None:
    """The last ``day`` of a month before ``today``: this month's, or an earlier month's."""
    month_start = today.replace(day=1)
    for _ in range(3):
        found = _safe_date(month_start.year, month_start.month, day)
        if found is not None and found < today:
            return found
        month_start = (month_start - timedelta(days=1)).replace(day=1)
    return None


_PAST_ACT = re.compile(
    r"\b(?:paid|was|were|arrived|sent|signed|received|bought|ordered|moved|came|went|happened|started|"
    r"ended|left|got|did|had|collected|delivered|posted|emailed|called|rang|met|saw|dropped|cancelled|"
    r"renewed|expired|took|gave|made|settled|transferred)\b[^.!?;]{0,30}$",
    re.I,
)
"""A verb of a past act just before a day ("paid on the 11th", "signed it on the 24th"): the day may be
one gone by."""


def _endpoint(groups: tuple[str | Any, ...]) -> tuple[str, str | None, str | None]:
    """One end of a range as its pattern's groups found it: the hour, and the minutes and am/pm if given."""
    hour, minute, suffix = groups
    return str(hour), minute, suffix


_DIGIT = re.compile(r"\d")
_DIGIT_NEEDED = "<a digit>"
_HINTS: dict[re.Pattern[str], tuple[str, ...]] = {
    _ISO_DATE: (_DIGIT_NEEDED,),
    _DAY_SPAN: (_DIGIT_NEEDED,),
    _DAY_AFTER: ("day after",),
    _END_OF_MONTH: ("end of",),
    _DAY_MONTH: (_DIGIT_NEEDED,),
    _MONTH_DAY: (_DIGIT_NEEDED,),
    _THE_NTH: (_DIGIT_NEEDED,),
    _BARE_NTH: (_DIGIT_NEEDED,),
    _SLASH_DATE: (_DIGIT_NEEDED,),
    _DOTTED_DATE: (_DIGIT_NEEDED,),
    _CLOCK: (_DIGIT_NEEDED,),
    _DASH_RANGE: (_DIGIT_NEEDED,),
    _WORDED_RANGE: ("between", "from"),
    _PAST_TO: ("past", "after", "to"),
    _PAST_TO_NAMED: ("midnight", "noon", "midday"),
    _HALF_HOUR: ("half",),
    _HOUR_BEFORE_PERIOD: ("morning", "afternoon", "evening", "night"),
    _HOUR_SUFFIX: ("am", "a.m", "pm", "p.m", "o'clock"),
    _AT_HOUR: ("at", "from", "by", "around", "until", "till"),
    _NAMED_TIME: ("noon", "midday", "midnight"),
    _WORD_CLOCK: ("fifteen", "thirty", "forty"),
    _FULL_WEEKDAY: ("day",),
    _SHORT_WEEKDAY: ("mon", "tue", "wed", "thu", "fri", "sat", "sun"),
    _RELATIVE_DAY: (
        "tomorrow",
        "today",
        "tonight",
        "this",
        "yesterday",
        "last night",
        "tmrw",
        "tmw",
        "2moro",
        "tomoz",
    ),
}
"""What a text must hold (in lower case) for each pattern to match in it, any one of them: most texts lack
most, and a substring test costs far less than a search (the patterns are tried on every text read)."""


class _Reading:
    """The mentions of one text as they are found, each stretch of text read once."""

    def __init__(self, text: str, anchor: datetime) -> None:
        self.text = text
        self.lowered = text.lower()
        self.digit = _DIGIT.search(text) is not None
        self.today = anchor.date()
        self.found: list[Mention] = []
        self.taken: list[tuple[int, int, Mention]] = []

    def scan(self, pattern: re.Pattern[str]) -> Iterator[re.Match[str]]:
        """``pattern``'s matches in the text; none, without a search, when the text lacks what it needs."""
        hints = _HINTS[pattern]
        if any(self.digit if hint is _DIGIT_NEEDED else hint in self.lowered for hint in hints):
            return pattern.finditer(self.text)
        return iter(())

    def overlapping(self, begin: int, end: int) -> list[Mention]:
        return [mention for start, stop, mention in self.taken if begin < stop and start < end]

    def add(self, span: tuple[int, int], days: Iterable[date] = (), times: Iterable[time] = ()) -> bool:
        """Record a mention unless its text was already read (a date's digits are not a clock time)."""
        if self.overlapping(*span):
            return False
        times = frozenset(times)
        period = _PERIOD_AFTER.match(self.text, span[1]) if times else None
        if period is not None:  # "8 in the evening": the part of the day picks the reading
            times = _in_period(times, next(group for group in period.groups() if group).lower())
        elif len(times) > 1:  # "tomorrow evening, about half six": said just before, it picks too
            before = _PERIOD_BEFORE.search(self.text, max(0, span[0] - 40), span[0])
            if before is not None:
                times = _in_period(times, before.group(1).lower().removeprefix("to"))
        mention = Mention(span[0], frozenset(days), times)
        self.taken.append((span[0], span[1], mention))
        self.found.append(mention)
        return True

    def counts(self, match: re.Match[str], hour: str) -> bool:
        """Whether an hour written as a word counts something instead ("at one point", "half one of them")."""
        return not hour.isdigit() and _COUNTED_AFTER.match(self.text, match.end()) is not None

    def add_days(self) -> None:
        today = self.today
        for match in self.scan(_ISO_DATE):
            self.add(match.span(), [d for d in [_safe_date(*(int(g) for g in match.groups()))] if d])
        for match in self.scan(_DAY_SPAN):
            first, last, month = int(match.group(1)), int(match.group(3)), _month_number(match.group(4))
            if self.overlapping(*match.span()):
                continue
            self.add(match.span(1), _year_readings(today, month, first, match.group(5)))
            self.add(match.span(2), _year_readings(today, month, last, match.group(5)))
        for match in self.scan(_DAY_MONTH):
            month, day = _month_number(match.group(2)), int(match.group(1))
            self.add(match.span(), _year_readings(today, month, day, match.group(3)))
        for match in self.scan(_MONTH_DAY):
            month, day = _month_number(match.group(1)), int(match.group(2))
            self.add(match.span(), _year_readings(today, month, day, match.group(3)))
        for match in self.scan(_THE_NTH):
            day = int(match.group(1))
            if match.group(2):  # "of this month" says which month
                self.add(match.span(), [d for d in [_nth_of_month(today, day, match.group(2).lower())] if d])
                continue
            readings = {d for d in [_next_nth(today, day)] if d} | self._month_before(match.start(), day)
            if _PAST_ACT.search(self.text, max(0, match.start() - 60), match.start()):
                readings |= {d for d in [_last_nth(today, day)] if d}  # "paid on the 11th": maybe last 11th
            self.add(match.span(), readings)
        for match in self.scan(_DOTTED_DATE):
            day, month, year = int(match.group(1)), int(match.group(2)), match.group(3)
            self.add(match.span(), _year_readings(today, month, day, year))
        for match in self.scan(_BARE_NTH):
            if _AFTER_WEEKDAY.search(self.text, max(0, match.start() - 12), match.start()):
                day = int(match.group(1))
                self.add(
                    match.span(),
                    {d for d in [_next_nth(today, day)] if d} | self._month_before(match.start(), day),
                )
        for match in self.scan(_SLASH_DATE):
            first, second, year = int(match.group(1)), int(match.group(2)), match.group(3)
            self.add(
                match.span(),
                _year_readings(today, second, first, year) | _year_readings(today, first, second, year),
            )

    def _month_before(self, at: int, day: int) -> set[date]:
        """``day`` in the month of a date written earlier in the same sentence ("in on 2 June and out on
        the 5th": 5 June), as a reading beside the next such day: the sentence has set the month.
        """
        dated = [
            mention
            for start, stop, mention in self.taken
            if stop <= at and mention.days and not _SENTENCE_END.search(self.text, start, at)
        ]
        if not dated:
            return set()
        last = max(dated, key=lambda mention: mention.start)  # each of its readings sets a month
        return {found for known in last.days if (found := _safe_date(known.year, known.month, day))}

    def add_weekdays(self) -> None:
        text, today = self.text, self.today

        def dated(match: re.Match[str]) -> int | None:
            """Where in ``taken`` the date a weekday is written with stands ("Thursday 22 May", "Thursday
            the 12th"), or ``None``: the date says which day it is.
            """
            for position, (start, _, mention) in enumerate(self.taken):
                if (
                    start >= match.end()
                    and mention.days
                    and _WEEKDAY_TO_DATE.fullmatch(text[match.end() : start])
                ):
                    return position
            return None

        for match, weekday in self._weekday_matches():
            position = dated(match)
            if position is None:
                qualifier = (match.group(1) or "") if match.re is _FULL_WEEKDAY else ""
                readings = _weekday_readings(today, weekday, qualifier)
                if not qualifier and (
                    _NEXT_WEEK_NEAR.match(text[match.end() : match.end() + 40])
                    or _NEXT_WEEK_NEAR.search(text[max(0, match.start() - 16) : match.start()])
                ):
                    monday = today + timedelta(days=7 - today.weekday())
                    readings = frozenset({monday + timedelta(days=weekday)})
                if not qualifier and _PAST_ACT.search(text, max(0, match.start() - 60), match.start()):
                    # "the one I ordered on Thursday": maybe the Thursday gone by
                    readings |= _weekday_readings(today, weekday, "last")
                self.add(match.span(), readings)
            else:
                self._agree(position, weekday)

    def _weekday_matches(self) -> Iterator[tuple[re.Match[str], int]]:
        for match in self.scan(_FULL_WEEKDAY):
            yield match, _WEEKDAYS.index(match.group(2).lower())
        for match in self.scan(_SHORT_WEEKDAY):
            yield match, _WEEKDAY_ABBREVIATIONS[match.group(1)]

    def _agree(self, position: int, weekday: int) -> None:
        """Keep the readings of a date written with a weekday that fall on that weekday: "Thursday the
        12th" said on 14 June is 12 June, a Thursday, not the next 12th (a Saturday). A day of the month
        with no such reading among the months around is looked for there; none found, the date stands.
        """
        start, stop, mention = self.taken[position]
        fitting = {day for day in mention.days if day.weekday() == weekday}
        month_said = bool(
            _MONTH_IN.search(self.text, start, stop) or _DIGIT_DATE.search(self.text, start, stop)
        )
        # a date whose month is written stands, even on another weekday: "Friday 16 June" is 16 June (a
        # wrong weekday is the writer's slip, the date is what a check must read)
        if not fitting and not month_said and len({day.day for day in mention.days}) == 1:
            nth = next(iter(mention.days)).day
            candidates = (_nth_of_month(self.today, nth, which) for which in ("this", "next", "last"))
            fitting = next(
                ({day} for day in candidates if day is not None and day.weekday() == weekday), set()
            )
        if not fitting or fitting == set(mention.days):
            return
        agreed = Mention(mention.start, frozenset(fitting), mention.times)
        self.taken[position] = (start, stop, agreed)
        self.found = [agreed if found is mention else found for found in self.found]

    def add_relative_days(self) -> None:
        for match in self.scan(_RELATIVE_DAY):
            word = " ".join(match.group(1).lower().split())
            offset = _RELATIVE_OFFSETS.get(word, 0)
            self.add(match.span(), [self.today + timedelta(days=offset)])
        for match in self.scan(_END_OF_MONTH):
            which = (match.group(1) or "").lower()
            if which:
                first = _nth_of_month(self.today, 1, "next" if which == "next" else "this")
                months = [first] if first else []
            else:
                month = _month_number(match.group(2))
                months = [d for d in (_safe_date(self.today.year + k, month, 1) for k in (0, 1)) if d]
            # "the end of June" is rough: its last week ("runs to the end of June" for a course ending the
            # 28th is right), the last day among them
            ends = [(start + timedelta(days=32)).replace(day=1) - timedelta(days=1) for start in months]
            self.add(match.span(), [end - timedelta(days=back) for end in ends for back in range(7)])

    def add_day_after(self) -> None:
        """The day after the latest day named before in the same sentence ("tomorrow and the day after")."""
        for match in self.scan(_DAY_AFTER):
            before = [
                mention
                for start, stop, mention in self.taken
                if stop <= match.start()
                and mention.days
                and not _SENTENCE_END.search(self.text, stop, match.start())
            ]
            if before:
                last = max(before, key=lambda mention: mention.start)
                self.add(match.span(), [day + timedelta(days=1) for day in last.days])

    def add_ranges(self) -> None:
        for match in self.scan(_DASH_RANGE):
            hour1, minute1, suffix1, hour2, minute2, suffix2 = match.groups()
            if suffix1 or suffix2 or minute1 or minute2:
                self._add_range(match, (hour1, minute1, suffix1), (hour2, minute2, suffix2))
        for match in self.scan(_WORDED_RANGE):
            groups = match.groups()
            between, start, last = groups[0:3], groups[3:6], groups[6:9]
            self._add_range(match, _endpoint(between if between[0] is not None else start), _endpoint(last))

    def _add_range(
        self,
        match: re.Match[str],
        first: tuple[str, str | None, str | None],
        last: tuple[str, str | None, str | None],
    ) -> None:
        starts, ends = _range_readings(first, last)
        period = _PERIOD_AFTER.match(self.text, match.end())
        if period is not None:
            part = next(group for group in period.groups() if group).lower()
            starts, ends = _in_period(starts, part), _in_period(ends, part)
        if starts and ends and not self.overlapping(*match.span()):
            middle = match.start() + 1  # both ends are recorded; the second only to keep the order
            self.taken.append((match.start(), match.end(), Mention(match.start(), times=starts)))
            self.found += [Mention(match.start(), times=starts), Mention(middle, times=ends)]

    def add_times(self) -> None:
        for match in self.scan(_PAST_TO_NAMED):  # before "at five" takes the hour of "at five to midnight"
            amount, direction = match.group(1).lower(), match.group(2).lower()
            minutes = _MINUTE_WORDS.get(" ".join(amount.replace("-", " ").split()))
            minutes = int(amount.split()[0]) if minutes is None else minutes
            if 0 < minutes < 60:
                base = 0 if match.group(3).lower() == "midnight" else 12
                whole = (base * 60 + (minutes if direction != "to" else -minutes)) % (24 * 60)
                self.add(match.span(), times=[time(whole // 60, whole % 60)])
        for match in self.scan(_PAST_TO):
            amount, direction = match.group(1).lower(), match.group(2).lower()
            hour = _hour_number(match.group(3))
            minutes = _MINUTE_WORDS.get(" ".join(amount.replace("-", " ").split()))
            if minutes is None:
                minutes = int(amount.split()[0])
                if direction != "past" and "minute" not in amount:
                    continue  # "2 to 4" is a range, "10 after 3" rarely a time: only "20 past 3"
            if not 0 < minutes < 60 or not 1 <= hour <= 12 or self.counts(match, match.group(3)):
                continue  # "five to ten people" counts people
            if direction == "to":
                hour, minutes = hour - 1 or 12, 60 - minutes
            self.add(match.span(), times=_clock_readings(hour, minutes, None))
        for match in self.scan(_HALF_HOUR):
            hour = _hour_number(match.group(1))
            if 1 <= hour <= 12 and not self.counts(match, match.group(1)):
                self.add(match.span(), times=_clock_readings(hour, 30, None))
        for match in self.scan(_HOUR_BEFORE_PERIOD):
            hour = _hour_number(match.group(1))
            self.add(match.span(), times=_clock_readings(hour, int(match.group(2) or 0), None))
        for match in self.scan(_CLOCK):
            written, suffix = match.group(1), match.group(3)
            if suffix is None and len(written) == 2 and written.startswith("0"):
                suffix = "am"  # "09:30" is written on the 24-hour clock: the morning only
            self.add(match.span(), times=_clock_readings(int(written), int(match.group(2)), suffix))
        for match in self.scan(_HOUR_SUFFIX):
            suffix = match.group(2)
            hour = _hour_number(match.group(1))
            self.add(match.span(), times=_clock_readings(hour, 0, None if "clock" in suffix else suffix))
        for match in self.scan(_AT_HOUR):
            if self.counts(match, match.group(1)):
                continue
            said = (match.group(2) or "").lower()
            minutes = {"": 0, "fifteen": 15, "thirty": 30}.get(said, 45)
            self.add(match.span(), times=_clock_readings(_hour_number(match.group(1)), minutes, None))
        for match in self.scan(_WORD_CLOCK):
            said = " ".join(match.group(2).lower().replace("-", " ").split())
            minutes = {"fifteen": 15, "thirty": 30}.get(said, 45)
            self.add(match.span(), times=_clock_readings(_hour_number(match.group(1)), minutes, None))
        for match in self.scan(_NAMED_TIME):
            said = match.group(1).lower()
            # midnight as a deadline is the last minute of the day as well: "by midnight" is "by 23:59"
            self.add(match.span(), times=[time(0, 0), time(23, 59)] if said == "midnight" else [time(12, 0)])


_DAY_ORDINAL_WORDS = ("first", "second", "third", "fourth", "fifth", "sixth", "seventh", "eighth", "ninth",
                      "tenth", "eleventh", "twelfth", "thirteenth", "fourteenth", "fifteenth", "sixteenth",
                      "seventeenth", "eighteenth", "nineteenth", "twentieth")  # fmt: skip
_DAY_ORDINALS = {word: number for number, word in enumerate(_DAY_ORDINAL_WORDS, start=1)}
_DAY_ORDINAL = re.compile(
    r"(?<=\bthe\s)(?:(twenty|thirty)[\s-])?(" + "|".join(_DAY_ORDINAL_WORDS) + r")\b"
    # a day, not "the first time": a weekday before it, "of" a month, or the phrase ending after it
    r"(?:(?=\s+of\s+(?:jan|feb|mar|apr|may|jun|jul|aug|sep|oct|nov|dec))|(?=\s*(?:[.,;:!?)]|$))|(?=\s+(?:at|from|until|till|and|or|when)\b))",
    re.I,
)
"""A day of the month as an ordinal in words after "the" ("Saturday the tenth", "the twenty-first of
May")."""
_ENDING = {1: "st", 2: "nd", 3: "rd", 21: "st", 22: "nd", 23: "rd", 31: "st"}
_WEEKDAY_ORDINAL = re.compile(
    r"(?<=day\sthe\s)(?:(twenty|thirty)[\s-])?(" + "|".join(_DAY_ORDINAL_WORDS) + r")\b", re.I
)
"""An ordinal after a weekday ("Saturday the tenth") is a day whatever follows."""


_DAY_PREPOSITION = re.compile(
    r"\b(?:on|by|until|till|from|before|after|since|starting|due|for)\s+the\s+$|day\s+the\s+$", re.I
)
"""What before "the first" makes it a day when no month follows: "paid on the first.", not "I keep the
first."."""
_OF_MONTH_AFTER = re.compile(r"\s+of\s+(?:jan|feb|mar|apr|may|jun|jul|aug|sep|oct|nov|dec)", re.I)


def _day_in_digits(match: re.Match[str]) -> str:
    """An ordinal day in words as digits ("tenth" as "10th"), padded to its length so positions hold."""
    text = match.string
    if not _OF_MONTH_AFTER.match(text, match.end()) and not _DAY_PREPOSITION.search(
        text, max(0, match.start() - 16), match.start()
    ):
        return match.group(0)  # "I keep the first." ranks; "due on the first." dates
    tens = {"twenty": 20, "thirty": 30}.get((match.group(1) or "").lower(), 0)
    number = tens + _DAY_ORDINALS[match.group(2).lower()]
    if number > 31:
        return match.group(0)
    return f"{number}{_ENDING.get(number, 'th')}".ljust(len(match.group(0)))


@lru_cache(maxsize=8192)
def mentions(text: str, anchor: datetime) -> tuple[Mention, ...]:
    """Every day and clock time named in ``text``, in order, resolved against ``anchor``.

    Remembered per text and reference moment: checks read the same messages again and again.
    """
    if "the " in text.lower():  # "the tenth" is the 10th
        text = _DAY_ORDINAL.sub(_day_in_digits, text)
        text = _WEEKDAY_ORDINAL.sub(_day_in_digits, text)
    reading = _Reading(text, anchor)
    reading.add_days()
    reading.add_ranges()
    reading.add_times()  # before the relative days: "8 tonight" is 20:00, and tonight is still today
    reading.add_relative_days()
    reading.add_weekdays()
    reading.add_day_after()
    if asks_library(text):
        _add_library_mentions(reading, anchor)
    return tuple(sorted(reading.found, key=lambda mention: mention.start))


def asks_library(text: str) -> bool:
    """Whether ``text`` is given to the date library: it holds a number and a phrase only the library reads
    (a count of units, "June the 2nd"); other texts are read by the rules alone, without importing it.
    """
    lowered = text.lower()
    if not any(word in lowered for word in ("minute", "hour", "day", "week", "fortnight", "the")):
        return False  # told without a search, as most texts are
    return _LIBRARY_CUE.search(text) is not None


_STRETCH_END = re.compile(r"[.,;!?\n]")


def _library_stretches(text: str) -> list[tuple[int, str]]:
    """The stretches of ``text`` the library is given, with where each begins: from the punctuation before
    a phrase only it reads to the punctuation after (a phrase the library takes has no comma anyway), so
    it searches a few words instead of a whole email.
    """
    stretches: dict[int, str] = {}
    for cue in _LIBRARY_CUE.finditer(text):
        before = [found.end() for found in _STRETCH_END.finditer(text, 0, cue.start())]
        begin = before[-1] if before else 0
        after = _STRETCH_END.search(text, cue.end())
        stretches[begin] = text[begin : after.start() if after else len(text)]
    return sorted(stretches.items())


def _add_library_mentions(reading: _Reading, anchor: datetime) -> None:
    """What dateparser finds that the rules did not read (see the module docstring)."""
    search, parse = _library(anchor)
    for offset, stretch in _library_stretches(reading.text):
        cursor = 0
        for phrase, _ in search(stretch) or ():
            at = stretch.find(phrase, cursor)
            if at < 0:
                continue
            cursor = at + len(phrase)
            if _NUMBER.search(phrase) and _RELATIVE_PHRASE.search(phrase):
                _add_library_phrase(reading, parse, phrase, offset + at)


def _add_library_phrase(reading: _Reading, parse: Callable[[str], Any], phrase: str, begin: int) -> None:
    """The day (where the phrase names one) and the time (where the rules read none) of a phrase."""
    parsed = parse(phrase)
    moment, period = parsed.date_obj, parsed.period
    if moment is None or period not in ("day", "time", "week"):
        return
    end = begin + len(phrase)
    known = reading.overlapping(begin, end)
    days = [] if any(m.days for m in known) or not _LIBRARY_DAY.search(phrase) else [moment.date()]
    times = [moment.time().replace(second=0, microsecond=0)] if period == "time" else []
    times = [] if any(m.times for m in known) else times
    if days or times:
        mention = Mention(begin, frozenset(days), frozenset(times))
        reading.taken.append((begin, end, mention))
        reading.found.append(mention)


@lru_cache(maxsize=64)
def _library(anchor: datetime) -> tuple[Callable[[str], Any], Callable[[str], Any]]:
    """The library's search and parser, set to read relative to ``anchor``, in its time zone."""
    # imported here, not with the module: only texts with a number and a day or time word need it
    from dateparser.date import DateDataParser
    from dateparser.search import search_dates

    settings: dict[str, Any] = {
        "RELATIVE_BASE": anchor.replace(tzinfo=None),
        "PREFER_DATES_FROM": "future",
        "TIMEZONE": anchor.tzname() or "UTC",
        "RETURN_AS_TIMEZONE_AWARE": False,
        "DATE_ORDER": "DMY",
    }
    parser = DateDataParser(languages=["en"], settings={**settings, "RETURN_TIME_AS_PERIOD": True})

    def search(text: str) -> Any:
        return search_dates(text, languages=["en"], settings=settings)

    return search, parser.get_date_data
