"""What a value is given for: a true value said of the wrong thing is a wrong detail.

The facts rule (:mod:`pare.scenarios.fact_details`) allows a detail any allowed text states. A text that
puts a true value on the wrong thing ("at the chapel at 3pm" where 3pm is the reception's, "the decaf for
£34" where £34 is the house blend's) states only given details, so it passes as a bag of details. This module
binds a value to what it is given for, by co-occurrence, and conservatively: the allowed texts are cut into
sentences, each remembered with the details it states and the content words it holds.

A value is *given for* the content words of every allowed sentence that states it, and *bound to* the
content words of an allowed clause that states it and no other value of its kind (content words: stop
words, numbers, day and month names and the words of details left out). A detail of the checked text is
*misbound* when a content word of its sentence is bound to a different value of its kind and no allowed
sentence stating this value holds any of its sentence's words: "see you at the chapel at 3pm" is misbound
where "The ceremony is at the chapel at 2pm." and "Drinks at 3pm in the garden." are the facts. A sentence
that states two values of the kind, or whose words the allowed texts bind to nothing, is left alone.
"""

from __future__ import annotations

import re
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass
from datetime import date, datetime
from typing import TYPE_CHECKING

from pare.scenarios.meaning import clauses

if TYPE_CHECKING:  # the facts rule reads details and binds them here: it imports this module
    from pare.scenarios.fact_details import Detail, Kind

BOUND_KINDS: frozenset[Kind] = frozenset({"time", "date", "money", "count", "street", "phone"})
"""The kinds of detail bound to what they are given for (a link or an email address is already one thing's;
a phone number is bound too, since a message may give one person's number as another's)."""

_SENTENCE_BREAK = re.compile(r"(?<=[.!?])\s+(?=[A-Z0-9\"'(])|\n+")


def _words(listed: str) -> frozenset[str]:
    """The words of ``listed``, written as one string for reading."""
    return frozenset(listed.split())


_WORD = re.compile(r"[A-Za-z][A-Za-z'-]*[A-Za-z]")
_STOP_WORDS = _words(
    """a about above after again against all also am an and any are as at be because been before being
    below between both but by can cannot could did do does doing done down during each either else even
    ever every few for from further get gets got had has have having he her here hers herself him himself
    his how i if in into is it its itself just let like may me might mine more most much must my myself
    near need needs neither no nor not now of off on once one only onto or other our ours ourselves out
    over own per please same shall she should since so some such than that the their theirs them
    themselves then there these they this those through till to too under until up upon us very via was
    we were what when where whether which while who whom whose why will with within without would yet you
    your yours yourself yourselves ok okay yes thanks thank hi hello dear let's it's i'm i've i'll i'd
    we're we've we'll you're you've you'll that's there's don't doesn't didn't won't can't isn't aren't
    wasn't weren't today tomorrow tonight yesterday morning afternoon evening night noon midnight week
    weeks day days month months year years time times am pm o'clock half quarter past
    booked book booking told tell said say says confirm confirmed confirmation sent send message note
    reminder set added add expect expected expecting arrive arrives arriving arrival come comes coming
    start starts starting work works working meet meeting see seeing leave leaving collect collecting
    collection pickup ready free available back home sure great good fine gone except suit suits regards
    kind best cheers hope love wish wishes accept accepted number phone mobile landline tel call ring text
    whatsapp contact reach"""
)
"""Words that bind a value to nothing: function words, words of time, and the verbs any message about a
detail uses (a detail is "booked" or "confirmed" whatever it is of)."""
_DAY_AND_MONTH_NAMES = _words(
    """monday tuesday wednesday thursday friday saturday sunday mon tue tues wed thu thur thurs fri sat sun
    january february march april may june july august september october november december jan feb mar apr
    jun jul aug sep sept oct nov dec"""
)
_NUMBER_WORDS = _words(
    """zero one two three four five six seven eight nine ten eleven twelve thirteen fourteen fifteen
    sixteen seventeen eighteen nineteen twenty thirty forty fifty sixty seventy eighty ninety hundred
    thousand million first second third fourth fifth sixth seventh eighth ninth tenth couple pair dozen
    pounds pound quid dollars dollar euros euro pence cents cent"""
)


def content_words(text: str, left_out: Iterable[tuple[int, int]] = ()) -> frozenset[str]:
    """The words of ``text`` that may name what a value is for: lowercased, without stop words, numbers,
    day and month names, the words inside the spans ``left_out`` (the details themselves), and with a
    plural's ``s`` dropped ("tickets" is "ticket").
    """
    for start, end in left_out:
        text = text[:start] + " " * (end - start) + text[end:]
    found: set[str] = set()
    for match in _WORD.finditer(text):
        word = match.group(0).lower().strip("'-")
        if len(word) < 3 or word in _STOP_WORDS or word in _DAY_AND_MONTH_NAMES or word in _NUMBER_WORDS:
            continue
        found.add(_singular(word))
    return frozenset(found)


def _singular(word: str) -> str:
    """``word`` without a possessive, plural or verb ending ("tickets", "picked", "picking" are "ticket",
    "pick", "pick"): a crude match of word forms, enough for co-occurrence (a form it misses only binds
    less).
    """
    if word.endswith("'s"):
        word = word[:-2]
    for ending in ("ing", "ed", "es", "s"):
        if len(word) > len(ending) + 3 and word.endswith(ending) and not word.endswith("ss"):
            return word[: -len(ending)]
    return word


def _keyed(detail: Detail) -> frozenset[object]:
    """``detail``'s readings as values are compared here: a day with its weekday (a weekday alone names the
    day of that weekday), an amount by its value (one written without its currency is the same amount).
    """
    if detail.kind == "money":
        return frozenset(one[1] for one in detail.readings if isinstance(one, tuple) and len(one) == 2)
    if detail.kind == "phone":  # with or without the country code: the same number by its last nine digits
        return frozenset(str(one)[-9:] for one in detail.readings)
    if detail.kind != "date":
        return detail.readings
    return detail.readings | {("weekday", day.weekday()) for day in detail.readings if isinstance(day, date)}


@dataclass(frozen=True, slots=True)
class _Binding:
    """A clause of an allowed text that states one value of a kind: its words are that value's."""

    kind: Kind
    readings: frozenset[object]
    shown: str
    words: frozenset[str]


@dataclass(frozen=True, slots=True)
class Misbinding:
    """A value said of the wrong thing: ``word`` is what the checked text binds it to, which the allowed
    texts give another value of this kind for.
    """

    detail: Detail
    word: str
    other: str
    """The value the allowed texts give for ``word`` (as one of them writes it)."""


class Bindings:
    """What the allowed texts give each value for.

    A value is *given for* every content word of a sentence that states it (generous: a word anywhere in
    the sentence clears a value), and *bound to* the content words of a clause that states it and no other
    value of its kind (strict: a list of values or a sentence of several binds nothing).
    """

    def __init__(self, read: Callable[[str, datetime], Sequence[Detail]]) -> None:
        self._read = read
        self._given: list[tuple[tuple[Detail, ...], frozenset[str]]] = []
        self._bound: list[_Binding] = []

    def add(self, text: str, anchor: datetime) -> None:
        """Remember the sentences and clauses of ``text``, their days read as of ``anchor``."""
        for piece in _SENTENCE_BREAK.split(text):
            stated = self._read(piece, anchor) if piece.strip() else ()
            found = tuple(one for one in stated if one.kind in BOUND_KINDS)
            if not found:
                continue
            self._given.append((found, content_words(piece, ((one.start, one.end) for one in stated))))
            for begin, end in _clause_spans(piece):
                inside = [one for one in found if begin <= one.start < end]
                for kind in {one.kind for one in inside}:
                    values = [one for one in inside if one.kind == kind]
                    if len({one.readings for one in values}) == 1:
                        words = content_words(piece[begin:end], _within(stated, begin, end))
                        if words:
                            self._bound.append(_Binding(kind, _keyed(values[0]), values[0].shown, words))

    def misbound(self, detail: Detail, text: str, stated: Sequence[Detail]) -> Misbinding | None:
        """Whether ``detail`` of ``text`` (which states ``stated``) is bound by its sentence to a thing an
        allowed clause gives a different value of its kind for, and to nothing an allowed sentence gives
        this value for (a sentence, not a clause: "Tom's train, the 8:10, ..." says what it is of before
        the comma).
        """
        if detail.kind not in BOUND_KINDS:
            return None
        begin, end = _sentence_span(text, detail.start, detail.end)
        if any(one.kind == detail.kind and one.readings != detail.readings and begin <= one.start < end
               for one in stated):  # fmt: skip
            return None  # two values of a kind in one sentence: which word goes with which is not read
        words = content_words(text[begin:end], _within(stated, begin, end))
        if not words:
            return None
        readings = _keyed(detail)
        for found, given in self._given:
            if not words.isdisjoint(given) and any(
                one.kind == detail.kind and not _keyed(one).isdisjoint(readings) for one in found
            ):
                return None  # the sentence names something this value is given for
        for bound in self._bound:
            if bound.kind == detail.kind and bound.readings.isdisjoint(readings):
                shared = words & bound.words
                if shared:
                    return Misbinding(detail, sorted(shared)[0], bound.shown)
        return None


def _within(stated: Iterable[Detail], begin: int, end: int) -> list[tuple[int, int]]:
    """Where the details of ``stated`` lie within ``begin``-``end``, relative to ``begin``."""
    return [(max(0, one.start - begin), min(end, one.end) - begin) for one in stated
            if one.start < end and one.end > begin]  # fmt: skip


def _clause_spans(text: str) -> list[tuple[int, int]]:
    """Where each clause of ``text`` lies (:func:`pare.scenarios.meaning.clauses`)."""
    spans, cursor = [], 0
    for clause in clauses(text):
        found = text.find(clause, cursor)
        if found < 0:
            return [(0, len(text))]
        spans.append((found, found + len(clause)))
        cursor = found + len(clause)
    return spans


def _sentence_span(text: str, start: int, end: int) -> tuple[int, int]:
    """Where the sentence of ``text`` that holds ``text[start:end]`` begins and ends."""
    begin = 0
    for match in _SENTENCE_BREAK.finditer(text):
        if match.end() <= start:
            begin = match.end()
        elif match.start() >= end:
            return begin, match.start()
    return begin, len(text)
