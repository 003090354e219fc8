"""The details a judge check's facts allow: a judge fallback that reads the facts as the judge does.

A judge model is told that a text stating a time, place, name or number the check's ``facts`` contradict
or do not contain fails. Without a judge model the check's fallback decides, and a fallback written for the
right words accepts them with a wrong detail beside them ("the drive will be clear by 8:30" when the facts
say 7:30). So the fallback also fails a text that states a detail of a kind a program reads reliably, where
the facts state details of that kind and none of the allowed texts states this one:

* ``time``: a clock time, read by :func:`pare.scenarios.timewords.mentions` (so "19:30", "7:30pm", "half
  seven in the evening" are one time; each end of a range counts). A time is allowed when one of its
  readings is one an allowed text names ("at 6" is 06:00 or 18:00: either will do).
* ``date``: a day named by a weekday, an explicit date or "today"/"tomorrow", read relative to when the
  text was sent; allowed texts are read relative to the scenario's start. Allowed when it is the same day.
* ``money``: an amount with its currency ("£14.99", "14.99 pounds", "GBP 14.99", "99p", "25 dollars and 70
  cents"), compared by currency and value (``£15`` is ``£15.00``); a figure with two decimals after a word
  of money ("Total: 87.00") is an amount in any currency, and a rough one ("about $59") may be 2 % off.
* ``phone``: a number of 9 to 15 digits, compared digit by digit whatever the grouping and with or without
  a country code (:mod:`pare.scenarios.numbers`).
* ``url`` and ``email``: compared without case, scheme, ``www.`` or a trailing slash; a link is also
  allowed when it is an allowed link without its query.
* ``count`` and ``part_of_day``: a number tied to what it counts ("size twelve", "the 4th floor") and
  "morning", "afternoon"... (:mod:`pare.scenarios.count_details`); read against a check's facts only,
  never in everything the assistant writes (:data:`WORLD_KINDS`).

The allowed texts are the facts, the criterion, and what the scenario's oracle and passing variants write
(their interventions' proposals and reports, and the text field the check reads of every action they
take): those solutions are right by definition, so a detail they state is not invented. Only the
assistant's own words are read: a forwarded message (below the forward rule) and quoted lines of a reply
(``>``) carry the original's details, which the assistant did not state. A check whose text legitimately
states other details opts out with ``other_details: <why>``.

A detail the allowed texts state still fails where the text says it of another thing than they give it
for ("at the chapel at 3pm" where 3pm is the reception's): :mod:`pare.scenarios.fact_binding`.
"""

from __future__ import annotations

import re
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, field
from datetime import UTC, date, datetime, time
from decimal import Decimal, InvalidOperation
from functools import lru_cache
from typing import Literal, NamedTuple, cast

from pare.scenarios.code_details import codes, same_code, same_street, streets
from pare.scenarios.count_details import (
    DURATIONS,
    NUMBER_IN_WORDS,
    counts,
    ordinal,
    parts_of_day,
    says_now,
    within,
    words_value,
)
from pare.scenarios.fact_binding import Bindings, Misbinding
from pare.scenarios.model import Scenario
from pare.scenarios.numbers import names_number
from pare.scenarios.person_details import NameFinder
from pare.scenarios.timewords import mentions

Kind = Literal[
    "time",
    "date",
    "money",
    "phone",
    "url",
    "email",
    "count",
    "part_of_day",
    "code",
    "street",
    "month",
    "percent",
    "person",
]
WORLD_KINDS: tuple[Kind, ...] = ("time", "date", "money", "phone", "url", "email")
"""The kinds read in everything the assistant writes (:mod:`pare.scenarios.invented`): a count or a part of
the day is often the assistant's own sum or summary, and a code, a street or a month is often the world's:
these five are read against a check's facts only."""

_FORWARD_RULE = re.compile(r"^-{3,}\s*Forwarded message\s*-{3,}\s*$", re.I | re.M)
"""Where a forward's own words end and the forwarded email begins (the email app writes this line)."""
_QUOTED_LINE = re.compile(r"^\s*>.*$", re.M)

_CURRENCY_SIGNS = {"£": "GBP", "$": "USD", "€": "EUR"}
_CURRENCY_WORDS = {"gbp": "GBP", "usd": "USD", "eur": "EUR", "pound": "GBP", "pounds": "GBP", "quid": "GBP",
                   "dollar": "USD", "dollars": "USD", "euro": "EUR", "euros": "EUR"}  # fmt: skip
_AMOUNT = r"(\d{1,3}(?:,\d{3})+(?!\d)|\d+)(?:[.,](\d{1,2}))?(?!\d)"
"""A number of money: "1,200", "14.99", and "25,70" as written where a comma marks the cents."""
_MONEY = re.compile(
    r"(?:([£$€])|(?<![A-Za-z])(GBP|USD|EUR)\s?)\s?" + _AMOUNT + r"(?:\s?(k)\b)?"
    r"|(?<![\d.,£$€])"
    + _AMOUNT
    + r"\s?(pounds?|quid|dollars?|euros?|GBP|USD|EUR|p(?!\.?\s?m\b)|pence)(?![A-Za-z])",
    re.I,
)
_PHONE = re.compile(r"(?<![\w+/.-])(?:\+|00)?\d[\d ().-]{7,20}\d(?![\w/])")
_ISO_DATE = re.compile(r"^\d{4}-\d{2}-\d{2}")
_URL = re.compile(r"(?:https?://|www\.)[^\s<>\"')\]]+", re.I)
_EMAIL = re.compile(r"(?<![\w.+-])[\w.+-]+@[\w-]+(?:\.[\w-]+)+")
_TRAILING = ".,;:!?"


@dataclass(frozen=True, slots=True)
class Detail:
    """One detail a text states: its kind, how it reads (the readings it may mean), and where it is."""

    kind: Kind
    readings: frozenset[object]
    shown: str
    """The detail as the verdict names it ("8:30", "£26.99")."""
    start: int
    end: int


def own_words(text: str) -> str:
    """``text`` without what it quotes: the forwarded email below a forward's rule, and ``>`` lines."""
    rule = _FORWARD_RULE.search(text)
    if rule is not None:
        text = text[: rule.start()]
    return _QUOTED_LINE.sub("", text) if ">" in text else text


def _clock_shown(times: frozenset[time]) -> str:
    """A time as a text may have meant it: "8:30" for 08:30 or 20:30, "19:30" for one reading."""
    first, *rest = sorted(times)
    if rest == [first.replace(hour=first.hour + 12)] if first.hour < 12 else False:
        return f"{first.hour or 12}:{first.minute:02d}"
    return " or ".join(moment.strftime("%H:%M") for moment in (first, *rest))


def _time_and_date_details(text: str, anchor: datetime) -> Iterable[Detail]:
    found = mentions(_DAY_RANGE.sub(_both_days, text), anchor)
    for index, mention in enumerate(found):
        end = _mention_end(text, mention.start)
        if mention.times:
            shown = _clock_shown(mention.times)
            readings: frozenset[object] = frozenset(mention.times)
            following = found[index + 1] if index + 1 < len(found) else None
            if following is not None and following.times and _is_range(text, mention.start, following.start):
                # a range ("between 9:00 and 10:00"): its ends, and the span between them
                spans = {
                    (first, last)
                    for first in mention.times
                    for last in following.times
                    if 0 < _minutes(last) - _minutes(first) < 12 * 60  # one reading of each end, not 9 to 22
                }
                readings |= {("span", first, last) for first, last in spans}
            if _ROUGHLY.search(text, max(0, mention.start - 16), mention.start) or _FROM_NOW.match(
                text, mention.start
            ):
                # "around quarter to ten" for a cab due at 09:46; "in an hour", sent at 10:32, for 11:30
                readings |= _near(mention.times)
            yield Detail("time", readings, shown, mention.start, end)
        if mention.days:
            shown = " or ".join(f"{day:%a} {day.day} {day:%b}" for day in sorted(mention.days))
            weekday = _WEEKDAY_ALONE.match(text, mention.start)
            days: frozenset[object] = frozenset(mention.days)
            if weekday is not None:  # "Saturday" said of the one a week on is still that Saturday
                days |= {("weekday", day.weekday()) for day in mention.days}
            yield Detail("date", days, shown, mention.start, end)


_ROUGHLY = re.compile(
    r"\b(?:around|about|roughly|approximately|approx\.?|circa|ca\.|just after|just before)\s+(?:at\s+)?$",
    re.I,
)
"""A word that makes the time after it a rough one."""
_FROM_NOW = re.compile(r"(?:in|within)\s+(?:an?|\d+|[a-z]+)\s+(?:minutes?|mins?|hours?)\b", re.I)
"""A time counted from when the text is sent ("in an hour", "in 20 minutes"): a rough one, since nobody
counts to the minute."""


def _near(times: Iterable[time]) -> frozenset[object]:
    """The clock times within five minutes of ``times``, each as ``("near", time)``: what a rough time may
    stand for (a reading that matches a time given exactly, not another text's rough one widened again).
    """
    found: set[object] = set()
    for moment in times:
        base = moment.hour * 60 + moment.minute
        found.update(("near", time(((base + step) // 60) % 24, (base + step) % 60)) for step in range(-5, 6))
    return frozenset(found)


_MONTH_NUMBERS = {name: number for number, names in enumerate(
    (("January", "Jan"), ("February", "Feb"), ("March", "Mar"), ("April", "Apr"), ("May",), ("June", "Jun"),
     ("July", "Jul"), ("August", "Aug"), ("September", "Sep", "Sept"), ("October", "Oct"),
     ("November", "Nov"), ("December", "Dec")), start=1) for name in names}  # fmt: skip
_MONTH_ALONE = re.compile(
    r"(?<![\w/])(?:(?P<which>[Ll]ast|[Tt]his|[Nn]ext)\s+)?(?P<month>" + "|".join(_MONTH_NUMBERS) + r")\b\.?"
    r"(?!\s*(?:the\s+)?\d{1,2}(?:st|nd|rd|th)?\b(?![\d,]\d))"
    r"(?:,?\s+(?P<year>(?:19|20)\d\d)\b|\s+(?P<relative>last|this|next)\s+year\b)?"
)
"""A month named without its day ("April 2024", "since April last year", "next March", "in June"),
capitalised: "may" and "march" are verbs too."""
_DAY_BEFORE = re.compile(r"\d{1,2}(?:st|nd|rd|th)?\s+(?:of\s+)?$")
_NOT_A_MONTH_AFTER = re.compile(r"\s+(?:I|we|you|he|she|they|it|be|have|not)\b")


def _month_details(text: str, anchor: datetime) -> Iterable[Detail]:
    """Every month named without its day, as its ``("month", year, month)`` readings: a year given or said
    ("last year"); "last"/"next" the one before or after now; else this year's or the nearest other.
    """
    for match in _MONTH_ALONE.finditer(text):
        name = match.group("month")
        if _DAY_BEFORE.search(text[: match.start()]) or (
            name == "May" and _NOT_A_MONTH_AFTER.match(text, match.end())
        ):
            continue
        month, year = _MONTH_NUMBERS[name], anchor.year
        which, relative = (match.group("which") or "").lower(), match.group("relative")
        if match.group("year"):
            years = {int(match.group("year"))}
        elif relative:
            years = {year + {"last": -1, "this": 0, "next": 1}[relative]}
        elif which == "last":
            years = {year if month < anchor.month else year - 1}
        elif which == "next":
            years = {year if month > anchor.month else year + 1}
        else:
            years = {year, year + 1 if month < anchor.month else year - 1}
        readings: frozenset[object] = frozenset(("month", one, month) for one in years)
        yield Detail("month", readings, match.group(0).strip(), *match.span())


def _minutes(moment: time) -> int:
    return moment.hour * 60 + moment.minute


def _is_range(text: str, first: int, second: int) -> bool:
    """Whether the times mentioned at ``first`` and ``second`` are the ends of one range."""
    return second == first + 1 or _RANGE_BETWEEN.match(text[first:second]) is not None


_RANGE_BETWEEN = re.compile(r"^[\w:.]+(?:\s?[ap]\.?m\.?)?\s*(?:-|\u2013|\u2014|to|and|until|till)\s*$", re.I)
"""What stands between the two ends of a range of times ("9:00 and 10:00", "9-10am", "7pm to 9pm")."""


def _both_days(match: re.Match[str]) -> str:
    """Days of a month as a range ("2 to 5 June") written as two dates, so the first is read as one too."""
    first, last, month = match.group(1), match.group(2), match.group(3)
    return f"{first} {month} to {last} {month}".ljust(len(match.group(0)))


_MONTHS = (r"(?:jan(?:uary)?|feb(?:ruary)?|mar(?:ch)?|apr(?:il)?|may|june?|july?|aug(?:ust)?|sept?(?:ember)?|"
           r"oct(?:ober)?|nov(?:ember)?|dec(?:ember)?)")  # fmt: skip
_DAY_RANGE = re.compile(
    r"(?<!\d)(?:the\s+)?(\d{1,2})(?:st|nd|rd|th)?\s*(?:to|-|\u2013|until|till)\s*(?:the\s+)?"
    r"(\d{1,2})(?:st|nd|rd|th)?\s+(?:of\s+)?(" + _MONTHS + r")\b",
    re.I,
)
"""Days of one month given as a range: "2 to 5 June", "the 2nd to the 5th of June"."""
_WEEKDAY_ALONE = re.compile(
    r"(?:(?:next|this)\s+)?(?:mon|tue|wed|thu|fri|sat|sun)[a-z]*\.?(?!,?\s*(?:the\s+)?\d)", re.I
)
"""A weekday named without its date: it matches the facts' day of that weekday, whichever week."""
_ADDRESS = re.compile(
    r"(?<![\d:.])\d{1,4}[A-Za-z]?(?:\s+[A-Z][a-z]+){1,3}\s+(?:Road|Rd|Way|Street|St|Lane|Close|Avenue|Ave|"
    r"Drive|Place|Court|Terrace|Gardens|Crescent|Square|Row|Hill|Park|Grove|Mews|Walk)\b"
)
"""A street address ("3 Heron Way"): its number is no hour."""


def _mention_end(text: str, start: int) -> int:
    """Where the words of a mention beginning at ``start`` roughly end (for the excerpt only)."""
    found = re.compile(r"\S+(?:\s+\S+)?").match(text, start)
    return found.end() if found else start


def _money_details(text: str) -> Iterable[Detail]:
    if not any(sign in text for sign in "£$€") and not re.search(r"\d\s?[a-zA-Z]|\d\.\d\d", text):
        return
    for match in _MONEY.finditer(text):
        sign, code, whole, cents, thousands, whole2, cents2, word = match.groups()
        end = match.end()
        if word is not None and cents2 is None and word.lower() not in ("p", "pence"):
            spoken = _CENTS_AFTER.match(text, end)  # "25 dollars and 70 cents" is $25.70
            if spoken is not None:
                cents2, end = spoken.group(1).rjust(2, "0"), spoken.end()
        if whole is not None:
            currency = _CURRENCY_SIGNS[sign] if sign else code.upper()
            value = _decimal(whole, cents) * (1000 if thousands else 1)
        else:
            lowered = word.lower()
            if lowered in ("p", "pence"):
                if cents2 is not None:
                    continue  # "2.5p" is no price anyone writes
                currency, value = "GBP", _decimal(whole2, None) / 100
            else:
                currency, value = _CURRENCY_WORDS[lowered], _decimal(whole2, cents2)
        if value is not None:
            yield _amount(text, currency, value, match.start(), end)
    for match in _BARE_AMOUNT.finditer(text):  # "Total: 87.00": money in all but its currency
        value = Decimal(match.group("figure").replace(",", ""))
        yield _amount(text, _ANY_CURRENCY, value, match.start("figure"), match.end("figure"))


def _amount(text: str, currency: str, value: Decimal, start: int, end: int) -> Detail:
    """The amount ``text[start:end]`` of ``value`` in ``currency``, with what the words around it say it is:
    a difference of two amounts ("$40 less") or a rough one ("about $59").
    """
    value = value.normalize()
    readings: set[object] = {(currency, value)}
    before = text[max(0, start - 24) : start]
    if _DIFFERENCE_AFTER.match(text, end) or _DIFFERENCE_BEFORE.search(before):
        readings.add(("difference", currency, value))
    if _ROUGH_AMOUNT.search(before):
        readings.add(("about", currency, value))
    if _SHARE_AFTER.match(text, end) or _SHARE_BEFORE.search(before):
        readings.add(("share", currency, value))
    return Detail("money", frozenset(readings), text[start:end].strip(), start, end)


_ANY_CURRENCY = "?"
"""The currency of an amount written without one ("Total: 87.00"): it matches a given amount in any."""
_CENTS_AFTER = re.compile(r"\s+(?:and\s+)?(\d{1,2})\s?(?:cents?|c)\b", re.I)
_BARE_AMOUNT = re.compile(
    r"\b(?:total|subtotal|paid|pay|costs?|saves?|saving|price|balance|refund(?:ed)?|charged?)\b"
    r"(?:\s+(?:of|is|was|will be|comes to|came to|you|us|me|her|him|them))*\s*[:=]?\s*"
    r"(?P<figure>\d{1,3}(?:,\d{3})*\.\d{2}|\d+\.\d{2})(?![\d.,]*\d)(?!\s?(?:%|per\s?cent|[a-zA-Z£$€]))",
    re.I,
)
"""A figure with two decimals after a word of money, with no currency ("Total: 87.00", "saves you
175.20"): an amount the facts must give, whatever its currency."""
_ROUGH_AMOUNT = re.compile(
    r"(?:about|around|roughly|approximately|approx\.?|circa|nearly|almost|just\s+(?:under|over)|some|~)\s*$",
    re.I,
)
"""A word that makes the amount after it a rough one: it stands for a given amount within 2 %."""


_DIFFERENCE_AFTER = re.compile(
    r"\s*(?:less|more|cheaper|dearer|extra|off|under|over|higher|lower|up|down|saved|saving|difference|left|"
    r"remaining|to spare|in change)\b",
    re.I,
)
_DIFFERENCE_BEFORE = re.compile(
    r"(?:sav(?:e|es|ed|ing)(?:\s+(?:you|us|me|her|him|them))?|difference\s+of|extra|up\s+by|down\s+by|rise\s+of|increase\s+of|"
    r"reduction\s+of|discount\s+of|cheaper\s+by)\s*$",
    re.I,
)
"""Words that say an amount is what two amounts differ by ("$40 less", "saves $6.50", "up by £70", "$44
left")."""
_SHARE_AFTER = re.compile(
    r"\s*(?:each|apiece|a\s+head|per\s+(?:head|person|night|day|week|month|item|ticket|pair)|"
    r"an?\s+(?:night|day|week|month|person|ticket))\b",
    re.I,
)
_SHARE_BEFORE = re.compile(
    r"(?:half(?:\s+is|\s+of\s+it)?|(?:your|his|her|their|my|our|each)\s+(?:half|share|part|bit)(?:\s+is|\s+comes\s+to)?|"
    r"split\s+(?:\w+\s+)?(?:ways?|evenly)?,?\s*(?:so|that's|that\s+is)?)\s*$",
    re.I,
)
"""Words that say an amount is a share of a given one: a rate ("3.30 EUR a night" of 9.90 for three nights),
what each pays ("$27 each"), a half ("your half is $27")."""
_MOST_SHARES = 31
"""The most parts a share is worked out of (a month's nights)."""


_MONEY_IN_WORDS = re.compile(
    rf"(?<![\w-])(?P<whole>{NUMBER_IN_WORDS})\s+(?P<unit>pounds?|quid|dollars?|bucks|euros?)"
    rf"(?:\s+(?:and\s+)?(?P<cents>{NUMBER_IN_WORDS}|\d{{1,2}})(?:\s+(?:pence|p|cents?))?)?(?![\w-])",
    re.I,
)
"""An amount in words: "ninety-six pounds forty", "forty-eight dollars and forty-nine cents"."""
_WORD_CURRENCIES = {"pound": "GBP", "quid": "GBP", "dollar": "USD", "buck": "USD", "euro": "EUR"}


_PERCENT = re.compile(
    rf"(?<![\w.,-])(?:(?P<digits>\d{{1,3}}(?:\.\d{{1,2}})?)|(?P<words>{NUMBER_IN_WORDS}))"
    r"(?:\s?%|[\s-]?per[\s-]?cent\b)",
    re.I,
)
""""12%", "12.5 per cent", "ten-percent": a share, read where the facts give one ("a 15% discount" where
it is 12%)."""


def _percent_details(text: str) -> Iterable[Detail]:
    if "%" not in text and "cent" not in text.lower():
        return
    for match in _PERCENT.finditer(text):
        digits = match.group("digits")
        value = Decimal(digits) if digits else words_value(match.group("words"))
        if value is not None:
            yield Detail("percent", frozenset({("percent", Decimal(value).normalize())}), match.group(0),
                         *match.span())  # fmt: skip


def _money_in_words(text: str) -> Iterable[Detail]:
    for match in _MONEY_IN_WORDS.finditer(text):
        whole = words_value(match.group("whole"))
        cents_written = match.group("cents")
        cents = None if cents_written is None else (
            int(cents_written) if cents_written.isdigit() else words_value(cents_written)
        )  # fmt: skip
        if whole is None or (cents_written is not None and (cents is None or cents > 99)):
            continue
        currency = _WORD_CURRENCIES[match.group("unit").lower().rstrip("s")]
        value = (Decimal(whole) + Decimal(cents or 0) / 100).normalize()
        yield Detail("money", frozenset({(currency, value)}), match.group(0), *match.span())


_FIGURE = re.compile(
    r"(?<![\d.,])(?P<figure>\d{1,3}(?:,\d{3})+(?:\.\d{2})?|\d+\.\d{2})(?![\d.,]\d)"
    r"|\b(?:excess|price|cost|fee|deposit|rent|fare|total|premium|balance|refund|charge|budget|limit)\s+"
    r"(?:of\s+|is\s+|:\s*)?(?P<after_word>\d+)(?![\d.,]\d)",
    re.I,
)
"""A figure written like money without a currency: with thousands separators or two decimals, or after a
word of money ("excess 350")."""


@lru_cache(maxsize=1024)
def _shares(amounts: frozenset[Decimal]) -> frozenset[Decimal]:
    """What one of ``amounts`` is of another and by how much it differs from it, in percent (of at most 40
    amounts, as for :func:`_differences`): "a 12% rise" from $2,050 to $2,296, "about 89%" of the limit.
    """
    if len(amounts) > 40:
        return frozenset()
    found: set[Decimal] = set()
    for part in amounts:
        for whole in amounts:
            if whole > 0 and part != whole:
                found.add(100 * part / whole)
                found.add(abs(100 * (part - whole) / whole))
    return frozenset(found)


@lru_cache(maxsize=1024)
def _differences(amounts: frozenset[Decimal]) -> frozenset[Decimal]:
    """What two of ``amounts`` differ by (of at most 40 amounts: a text's own arithmetic on the amounts it
    was given, not a search over every number of a long statement). Sums are not read: a total twice over
    is the usual wrong amount ("charged twice").
    """
    if len(amounts) > 40:
        return frozenset()
    ordered = sorted(amounts)
    found = {(high - low).normalize() for index, low in enumerate(ordered) for high in ordered[index + 1 :]}
    return frozenset(found)


_ROUGHLY_WITHIN = Decimal("0.02")
"""How far a rough amount ("about $59") may be from the given one it stands for, as a share of it."""


def _decimal(whole: str, cents: str | None) -> Decimal:
    try:
        return Decimal(whole.replace(",", "") + (f".{cents}" if cents else ""))
    except InvalidOperation:  # pragma: no cover - the pattern admits digits only
        return Decimal(0)


def _phone_details(text: str) -> Iterable[Detail]:
    for match in _PHONE.finditer(text):
        written = match.group(0).strip()
        digits = re.sub(r"\D", "", written)
        if 9 <= len(digits) <= 15 and not _ISO_DATE.match(written) and "\n" not in written:
            # "+31 (0)6 ...": the trunk zero in brackets is dialled at home only, so the number is both
            trunk = {re.sub(r"\D", "", written.replace("(0)", ""))} if "(0)" in written else set()
            yield Detail("phone", frozenset({digits, *trunk}), written, *match.span())


def _url_key(url: str) -> str:
    key = url.lower().rstrip(_TRAILING)
    key = re.sub(r"^https?://", "", key)
    return key.removeprefix("www.").rstrip("/")


def _url_details(text: str) -> Iterable[Detail]:
    if "http" not in text and "www." not in text:
        return
    for match in _URL.finditer(text):
        written = match.group(0).rstrip(_TRAILING)
        yield Detail(
            "url", frozenset({_url_key(written)}), written, match.start(), match.start() + len(written)
        )


def _email_details(text: str) -> Iterable[Detail]:
    if "@" not in text:
        return
    for match in _EMAIL.finditer(text):
        written = match.group(0).rstrip(_TRAILING)
        yield Detail(
            "email", frozenset({written.lower()}), written, match.start(), match.start() + len(written)
        )


def _blank(text: str, start: int, end: int) -> str:
    """``text`` with ``text[start:end]`` blanked out (read already, as another kind of detail)."""
    return text[:start] + " " * (end - start) + text[end:]


@lru_cache(maxsize=4096)
def details(text: str, anchor: datetime) -> tuple[Detail, ...]:
    """Every detail of a readable kind ``text`` states, its days read as of ``anchor``.

    Remembered per text and moment: a check reads the same messages on every evaluation of an episode.
    """
    found: list[Detail] = [*_url_details(text), *_email_details(text)]
    # a link or an address holds digits and words that are not times, prices or phone numbers
    masked = text
    for detail in found:
        masked = masked[: detail.start] + " " * (detail.end - detail.start) + masked[detail.end :]
    found += [
        *_money_details(masked),
        *_money_in_words(masked),
        *_percent_details(masked),
        *_phone_details(masked),
    ]
    for detail in found:
        masked = masked[: detail.start] + " " * (detail.end - detail.start) + masked[detail.end :]
    placed = list(streets(masked))
    for street in placed:  # a house number is no hour, no count and no code
        masked = _blank(masked, street.start, street.end)
    masked = _ADDRESS.sub(lambda address: " " * len(address.group(0)), masked)
    counted = list(counts(masked))
    for count in counted:  # "the 4th floor" is no date
        if ordinal(count):
            masked = _blank(masked, count.start, count.end)
    timed = list(_time_and_date_details(masked, anchor))
    found += timed
    found += _month_details(masked, anchor)
    found += (
        Detail("count" if one.reading[0] == "count" else "part_of_day", frozenset(one.readings), one.shown,
               one.start, one.end)
        for one in (*counted, *parts_of_day(masked))
    )  # fmt: skip
    found += (Detail("street", frozenset({one.reading}), one.shown, one.start, one.end) for one in placed)
    for detail in (*timed, *(one for one in found if one.kind == "count")):  # "7pm", "2-bed" are no codes
        masked = _blank(masked, detail.start, detail.end)
    found += (
        Detail("code", frozenset({one.reading}), one.shown, one.start, one.end) for one in codes(masked)
    )
    return tuple(found)


class Stray(NamedTuple):
    """A detail the facts rule rejects, the words around it, and why ("which the facts do not give")."""

    detail: Detail
    around: str
    why: str


def stated_amounts(text: str) -> list[tuple[Decimal, bool]]:
    """The money amounts ``text`` states, by value (the currency is not compared: a story has one), each
    with whether it is said to be rough ("about $59").
    """
    found: list[tuple[Decimal, bool]] = []
    for detail in details(text, _NO_MOMENT):
        if detail.kind == "money":
            # an amount is (currency, value); ("difference", currency, value) says how it was put
            rough = any(isinstance(one, tuple) and one[0] == "about" for one in detail.readings)
            found += [(one[1], rough) for one in detail.readings if isinstance(one, tuple) and len(one) == 2]
    return found


_NO_MOMENT = datetime(2000, 1, 1, tzinfo=UTC)
"""The moment amounts are read as of: they name no day."""


@dataclass(slots=True)
class AllowedDetails:
    """The details a judge check's text may state: compiled once per check (on its compiled rule).

    ``facts`` decide which kinds are checked (those they state a detail of) and give the first allowed
    details; ``more`` gives the other allowed texts (the criterion's, the solutions'), read only when a
    text states a detail the facts do not give, so a check whose texts keep to the facts never reads them.
    """

    start: datetime
    kinds: frozenset[Kind]
    _allowed: dict[Kind, set[object]]
    _more: Callable[[], Sequence[str]] | None = None
    _texts: list[str] = field(default_factory=list)
    _figures: set[Decimal] = field(default_factory=set)
    """Money-like figures the allowed texts give without a currency ("salary 41,500", "86.40"): an amount of
    that value is given, in any currency."""
    counted: frozenset[str] = frozenset()
    """The labels of the counts the facts give: only counts of these are checked ("2 tickets" is read only
    where the facts count tickets)."""
    within_ranges: bool = True
    """Whether a time inside a range an allowed text gives is allowed ("between 9 and 10" allows 9:30)."""
    _bindings: Bindings = field(default_factory=lambda: Bindings(details))
    """The allowed texts' sentences: what each value is given for (:mod:`pare.scenarios.fact_binding`)."""
    _names: NameFinder = field(default_factory=lambda: NameFinder.of(()))
    """The world's people, read as ``person`` details (:meth:`know_people`)."""

    @classmethod
    def of(cls, facts: Sequence[str], start: datetime, more: Callable[[], Sequence[str]]) -> AllowedDetails:
        """The details ``facts`` give (read as of ``start``), with ``more`` to widen them when needed."""
        allowed = cls(start, frozenset(), {}, more)
        allowed._add(facts)
        kinds = set(allowed._allowed)
        if "time" in kinds:  # facts that give a time give its part of the day
            kinds.add("part_of_day")
        if allowed._figures:  # "a salary of 41,500" gives an amount, without its currency
            kinds.add("money")
        allowed.kinds = frozenset(kinds)
        counted = allowed._allowed.get("count", set())
        labels = frozenset(cast("tuple[str, tuple[str, str]]", one)[1][0] for one in counted)
        allowed.counted = labels | DURATIONS if not labels.isdisjoint(DURATIONS) else labels
        return allowed

    @classmethod
    def of_texts(cls, texts: Iterable[str], start: datetime, kinds: frozenset[Kind]) -> AllowedDetails:
        """The details ``texts`` give (read as of ``start``), checked for every kind of ``kinds``: a time
        is allowed only when one of them names it (not when it falls inside a range one of them gives).
        """
        allowed = cls(start, kinds, {}, within_ranges=False)
        allowed.add(texts)
        return allowed

    def add(self, texts: Iterable[str], anchor: datetime | None = None) -> None:
        """Allow the details ``texts`` state, their days read as of ``anchor`` (default: the start)."""
        self._add(texts, anchor)

    def know_people(self, names: NameFinder, owner: Iterable[str]) -> None:
        """Read the world's people (:mod:`pare.scenarios.person_details`) in the allowed texts and the
        checked ones: checked where the facts name one of them, the phone's ``owner`` always allowed.
        """
        self._names = names
        facts_name_someone = False
        for text in self._texts:  # the facts, read before the world's people were known
            found = [one.reading for one in names.find(text)]
            self._allowed.setdefault("person", set()).update(found)
            facts_name_someone = facts_name_someone or bool(found)
        if facts_name_someone:
            self._allowed["person"].update(("person", name) for name in owner)
            self.kinds = self.kinds | {"person"}

    def add_readings(self, kind: Kind, readings: Iterable[object]) -> None:
        """Allow details of ``kind`` by their readings (a value a program wrote rather than a text)."""
        self._allowed.setdefault(kind, set()).update(readings)

    def _add(self, texts: Iterable[str], anchor: datetime | None = None) -> None:
        for text in texts:
            self._texts.append(text)
            self._bindings.add(text, anchor or self.start)
            self._figures.update(
                Decimal((match.group("figure") or match.group("after_word")).replace(",", "")).normalize()
                for match in _FIGURE.finditer(text)
            )
            if self._names.pattern is not None:
                self._allowed.setdefault("person", set()).update(
                    one.reading for one in self._names.find(text)
                )
            for detail in details(text, anchor or self.start):
                given = self._allowed.setdefault(detail.kind, set())
                given.update(detail.readings)
                if detail.kind == "date":  # a weekday alone in a text matches any of these days' weekdays
                    given.update(
                        ("weekday", day.weekday()) for day in detail.readings if isinstance(day, date)
                    )

    def allows(self, detail: Detail, sent: datetime) -> bool:
        """Whether ``detail`` (of a text sent at ``sent``) is one of an unchecked kind, or one an allowed
        text states.
        """
        if detail.kind not in self.kinds:
            return True
        if detail.kind == "count" and self._label(detail) not in self.counted:
            return True
        if self._given(detail, sent):
            return True
        if self._more is not None:  # widen once: the criterion and the solutions' texts
            more, self._more = self._more, None
            self._add(more())
            return self._given(detail, sent)
        return False

    def _given(self, detail: Detail, sent: datetime) -> bool:
        allowed = self._allowed.get(detail.kind, set())
        if not detail.readings.isdisjoint(allowed):
            return True
        if detail.kind == "count" and self._label(detail) in DURATIONS:  # "two days" for "48 hours"
            return any(
                _same_length(cast("tuple[str, tuple[str, str]]", one)[1], given[1])
                for one in detail.readings
                for given in allowed
                if isinstance(given, tuple) and given[0] == "count"
            )
        if detail.kind == "month":  # a day the allowed texts give gives its month
            days = self._allowed.get("date", set())
            return any(
                ("month", day.year, day.month) in detail.readings for day in days if isinstance(day, date)
            )
        if detail.kind == "time" and any(
            isinstance(one, tuple) and one[0] == "near" and one[1] in allowed for one in detail.readings
        ):
            return True  # a rough time ("around quarter to ten") near one given
        if detail.kind == "time":  # a time inside a range the allowed texts give
            return self.within_ranges and any(
                isinstance(span, tuple) and span[0] == "span" and span[1] <= moment <= span[2]
                for moment in detail.readings
                if isinstance(moment, time)
                for span in allowed
            )
        if detail.kind == "date":  # the day the text is sent on ("today") is no invented detail
            return sent.date() in detail.readings
        if detail.kind == "money":
            currency, value = next(
                cast("tuple[str, Decimal]", one)
                for one in detail.readings
                if isinstance(one, tuple) and len(one) == 2
            )
            amounts = [given for given in allowed if isinstance(given, tuple) and len(given) == 2]
            said_as_difference = ("difference", currency, value) in detail.readings
            same_currency = frozenset(
                amount[1]
                for amount in amounts
                if amount[0] == currency or _ANY_CURRENCY in (currency, amount[0])
            )
            if said_as_difference and value in _differences(same_currency):
                return True  # "$40 less", "saves £6.50": what two given amounts differ by
            if value == 0:
                return True  # "balance now $0.00", "nothing left to pay": no amount is stated
            if ("share", currency, value) in detail.readings and any(
                _shares_of(value, given) for given in same_currency
            ):
                return True  # "$27 each", "3.30 EUR a night": a given amount split evenly
            if ("about", currency, value) in detail.readings and any(
                abs(given - value) <= given * _ROUGHLY_WITHIN for given in same_currency
            ):
                return True  # "about $59" for $58.40
            if value in self._figures:
                return True  # the facts give the figure without its currency ("a salary of 41,500")
            used = {amount[0] for amount in amounts}  # a sign the scenario never uses is a slip of the sign
            return currency not in used and any(amount[1] == value for amount in amounts)
        if detail.kind == "percent":  # "an 11% rise": what one given amount is of another, near enough
            (reading,) = detail.readings
            share = cast("tuple[str, Decimal]", reading)[1]
            given_amounts = frozenset(
                cast("Decimal", given[1])
                for given in self._allowed.get("money", set())
                if isinstance(given, tuple) and len(given) == 2
            )
            return any(abs(share - ratio) <= 1 for ratio in _shares(given_amounts))
        if detail.kind == "part_of_day":  # named, or holding a time an allowed text gives
            (reading,) = detail.readings
            part = cast("tuple[str, str]", reading)[1]
            times = self._allowed.get("time", set())
            return any(
                within(part, moment) if isinstance(moment, time) else within(part, moment[1])
                for moment in times
                if isinstance(moment, time) or (isinstance(moment, tuple) and len(moment) == 3)
            ) or (says_now(detail.shown, 0) and within(part, sent.time()))
        if detail.kind == "code":  # "hx 20931" is HX-20931 read as two words: a part of 4 or more will do
            (reading,) = detail.readings
            code = cast("tuple[str, str]", reading)[1]
            return any(
                isinstance(given, tuple) and given[0] == "code" and same_code(given[1], code)
                for given in allowed
            )
        if detail.kind == "street":  # the same street, with the same number where both give one
            (reading,) = detail.readings
            name, number = cast("tuple[str, tuple[str, str]]", reading)[1]
            numbers = {
                given[1][1] for given in allowed
                if isinstance(given, tuple) and given[0] == "street" and same_street(given[1][0], name)
            }  # fmt: skip
            if not numbers:
                return False
            # a number the texts give for the street is the one: "9 Cedar Road" is wrong where they give 22,
            # even if another text names Cedar Road without one
            numbered = numbers - {""}
            return not number or not numbered or number in numbered
        if detail.kind == "phone":  # any grouping, with or without the country code
            return any(names_number(text, detail.shown) for text in self._texts)
        if detail.kind == "url":  # a link given without its query is the same link
            (key,) = detail.readings
            return any(
                isinstance(given, str) and given.split("?")[0] == key
                for given in self._allowed.get("url", ())
            )
        return False

    @staticmethod
    def _label(detail: Detail) -> str:
        return cast("tuple[str, tuple[str, str]]", next(iter(detail.readings)))[1][0]

    def stray(
        self,
        text: str,
        sent: datetime,
        also: Callable[[Detail, datetime], bool] | None = None,
        *,
        read_at: datetime | None = None,
    ) -> Stray | None:
        """The first detail of the assistant's own words in ``text`` (sent at ``sent``, its days read as of
        ``read_at``, default ``sent``: a reminder's as of when it fires) that no allowed text states (nor
        ``also`` allows, when given), or that the allowed texts give for another thing than the one it is
        said of (:mod:`pare.scenarios.fact_binding`), with the excerpt around it; ``None`` when every one
        is allowed.
        """
        if not self.kinds:
            return None
        words = own_words(text)
        stated = sorted(details(words, read_at or sent), key=lambda found: found.start)
        if "person" in self.kinds:
            people = (
                Detail("person", one.readings, one.shown, one.start, one.end)
                for one in self._names.find(words)
            )
            stated = sorted([*stated, *people], key=lambda found: found.start)
        for detail in stated:
            if not self.allows(detail, sent):
                if also is None or not also(detail, sent):
                    return Stray(
                        detail, excerpt(words, detail.start, detail.end), "which the facts do not give"
                    )
                continue
            misbound = self._misbound(detail, words, stated)
            if misbound is not None:
                return Stray(
                    detail,
                    excerpt(words, detail.start, detail.end),
                    f"which the facts give for another thing: for '{misbound.word}' they give "
                    f"{misbound.other}",
                )
        return None

    def _misbound(self, detail: Detail, text: str, stated: Sequence[Detail]) -> Misbinding | None:
        """Whether ``detail``, allowed by a direct reading, is said of a thing the allowed texts give a
        different value of its kind for (and this value for nothing it is said of); read against every
        allowed text before it is found so (the criterion and the solutions' too).
        """
        if detail.kind not in self.kinds or not _read_directly(detail, self._allowed.get(detail.kind, set())):
            return None
        found = self._bindings.misbound(detail, text, stated)
        if found is not None and self._more is not None:
            more, self._more = self._more, None
            self._add(more())
            found = self._bindings.misbound(detail, text, stated)
        return found

    def allows_read(self, detail: Detail, sent: datetime) -> bool:
        """Whether ``detail`` is of a kind these details read and one they allow (a kind they do not read
        is not allowed by them, unlike :meth:`allows`).
        """
        return detail.kind in self.kinds and self.allows(detail, sent)


def _shares_of(value: Decimal, given: Decimal) -> bool:
    """Whether ``value`` is ``given`` split evenly into 2 to 31 parts, to the cent."""
    return value > 0 and any(
        abs(value * parts - given) < Decimal("0.01") * parts for parts in range(2, _MOST_SHARES + 1)
    )


_MINUTES = {"minute": 1, "hour": 60, "day": 1440, "night": 1440, "week": 10080}
"""Lengths of time in minutes, where one unit is a fixed number of another."""
_ROUGH_DAYS = {"month": (28, 31), "year": (365, 366)}
"""Lengths of time in days, where one unit is a span of days: "a month" is 4 weeks or 30 days."""


def _same_length(said: tuple[str, str], given: tuple[str, str]) -> bool:
    """Whether two lengths of time, as ``(unit, number)``, are the same: "two days" and "48 hours", "a
    month" and "4 weeks", "a year" and "12 months".
    """
    (unit, number), (given_unit, given_number) = said, given
    try:
        value, given_value = Decimal(number), Decimal(given_number)
    except InvalidOperation:
        return False
    if unit in _MINUTES and given_unit in _MINUTES:
        return value * _MINUTES[unit] == given_value * _MINUTES[given_unit]
    if {unit, given_unit} == {"year", "month"}:
        return (value * 12 if unit == "year" else value) == (
            given_value * 12 if given_unit == "year" else given_value
        )
    for rough, fixed, rough_value, fixed_value in (
        (unit, given_unit, value, given_value),
        (given_unit, unit, given_value, value),
    ):
        if rough in _ROUGH_DAYS and fixed in _MINUTES and _MINUTES[fixed] >= 1440:
            low, high = _ROUGH_DAYS[rough]
            days = fixed_value * _MINUTES[fixed] / 1440
            return rough_value * low <= days <= rough_value * high
    return False


def _read_directly(detail: Detail, allowed: set[object]) -> bool:
    """Whether ``detail`` is one of ``allowed`` as it is written (an amount without its currency is any
    given amount of its value), not by a reading worked out from them (a difference, a time in a range).
    """
    if not detail.readings.isdisjoint(allowed):
        return True
    if detail.kind == "phone":  # with or without the country code
        ends = {str(one)[-9:] for one in detail.readings}
        return any(isinstance(one, str) and one[-9:] in ends for one in allowed)
    bare = {
        one[1]
        for one in detail.readings
        if isinstance(one, tuple) and len(one) == 2 and one[0] == _ANY_CURRENCY
    }
    return any(isinstance(one, tuple) and len(one) == 2 and one[1] in bare for one in allowed)


def excerpt(text: str, start: int, end: int, margin: int = 24) -> str:
    """The words around ``text[start:end]``, with "..." where the text goes on."""
    begin, stop = max(0, start - margin), min(len(text), end + margin)
    while begin > 0 and not text[begin - 1].isspace():
        begin += 1
        if begin >= start:
            break
    while stop < len(text) and not text[stop].isspace():
        stop -= 1
        if stop <= end:
            stop = end
            break
    piece = " ".join(text[begin:stop].split())
    return ("... " if begin > 0 else "") + piece + (" ..." if stop < len(text) else "")


def solution_texts(scenario: Scenario, field_name: str) -> list[str]:
    """What the oracle and the passing variants write: their proposals and reports, and the ``field_name``
    argument of every action they take (the field a judge check reads), in the scenario's order.
    """
    interventions = list(scenario.oracle.interventions)
    for variant in scenario.variants:
        if variant.teaches and variant.interventions is not None:
            interventions += variant.interventions
    texts: list[str] = []
    for intervention in interventions:
        texts += [intervention.proposal, intervention.report]
        for action in intervention.actions:
            value = action.args.get(field_name)
            if isinstance(value, str):
                texts.append(value)
    return texts
