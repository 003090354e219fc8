"""Value matchers: how a check says which argument values or state values it accepts.

Written in YAML as a plain value (``email-12``: equal to it), or as a mapping of operators that must all
hold::

    content: {contains: [thursday, "3"]}         # whole words, case-insensitive, every piece
    content: {affirms: thursday, mentions_time: day+2 18:15}   # read for meaning, not wording
    recipients: {same_set: [bob@x.org, ann@x.org]}
    start_datetime: {from: day+1 09:00, before: day+1 12:00}   # 09:00 in, 12:00 out (``by`` keeps it)
    updates: {start_datetime: day+1 10:00}        # a mapping of fields: each listed field must match

A mapping whose keys are not operators matches a mapping value field by field (unlisted fields are
ignored), or a list value holding at least one such mapping. Operators are listed in :data:`OPERATORS`.
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable, Iterator, Mapping, Sequence
from contextlib import contextmanager
from contextvars import ContextVar
from dataclasses import dataclass, field
from datetime import UTC, date, datetime, time
from functools import lru_cache, partial
from typing import Any

from pare.scenarios import meaning
from pare.scenarios.times import TimeFormatError, is_relative_time, parse_time

OPERATORS: dict[str, str] = {
    "equals": "equal to the value (times compare as times, whatever their format)",
    "contains": "text containing the string, or every string of a list, as whole words (case-insensitive; "
    "'wed' is not found in 'reviewed'; a '*' at a piece's end lets the word go on: 'view*'); for a list "
    "value, some element contains it",
    "contains_any": "text containing at least one of the strings, as whole words (case-insensitive)",
    "affirms": "text in which every string is mentioned in a clause without negation ('Thursday works' "
    "affirms thursday; 'Thursday does not work' does not)",
    "declines": "true: the text refuses, cancels or says something does not work; false: it does not",
    "mentions_day": "text naming this day (a time, absolute or relative to the start): 'Thu', '20 March', "
    "'tomorrow', '20/03'; mentions in negated clauses do not count",
    "mentions_clock": "text naming this clock time ('18:15' or a time): '6:15pm', '18.15', '18h15', 'at 6'",
    "mentions_time": "text naming this day together with this clock time (in one sentence, or as the text's "
    "only day and only time): 'Thursday at 6.15pm'",
    "regex": "text in which the regular expression is found (case-insensitive)",
    "one_of": "equal to one of the values",
    "same_set": "a list with the same elements in any order (text compared case-insensitively)",
    "min": "a number at least this",
    "max": "a number at most this",
    "after": "a time strictly after this (absolute or relative to the start); the bound itself fails",
    "from": "a time at or after this (absolute or relative to the start); the bound itself holds",
    "before": "a time strictly before this (absolute or relative to the start); the bound itself fails",
    "by": "a time at or before this (absolute or relative to the start); the bound itself holds",
    "present": "true: the value is given (not missing or null); false: it is not",
    "not": "a matcher that must not hold",
    "any_of": "a list of matchers of which at least one holds",
}

_DAY_ONLY = re.compile(r"\s*day\s*([+-]\s*\d+)?\s*")
_TIME_OPERATORS = ("after", "from", "before", "by", "mentions_day", "mentions_time")
TEXT_OPERATORS = frozenset(
    {
        "contains",
        "contains_any",
        "affirms",
        "declines",
        "regex",
        "mentions_day",
        "mentions_clock",
        "mentions_time",
    }
)
"""Operators that read text (they apply to text fields, or to lists and records of text)."""
NUMBER_OPERATORS = frozenset({"min", "max"})
TIME_OPERATORS = frozenset({"after", "from", "before", "by"})
"""Bounds on a time: ``after`` and ``before`` leave the bound out, ``from`` and ``by`` take it in."""
LIST_OPERATORS = frozenset({"same_set"})
_CHEAP_OPERATORS = frozenset({"equals", "one_of", "present", "min", "max"})
"""Operators that only compare values (an equal time text is read as a time, but seldom)."""


_WRITTEN_AT: ContextVar[datetime | None] = ContextVar("written_at", default=None)
"""When the text being read was written, where the caller knows it (see :func:`written_at`)."""
_DAY_READERS = frozenset({"mentions_day", "mentions_clock", "mentions_time"})


@contextmanager
def written_at(moment: datetime | None) -> Iterator[None]:
    """Read the days and times of texts as written at ``moment``, not at the start, inside the block.

    "Tomorrow" in a message sent on the second day of an episode is the third day; "the 2nd" is the next
    2nd after the message was sent. Callers that know when a text was sent (an action's log entry) wrap
    the matcher's test in this; elsewhere texts are read as written at the start.
    """
    token = _WRITTEN_AT.set(moment)
    try:
        yield
    finally:
        _WRITTEN_AT.reset(token)


def reading_moment(start: datetime) -> datetime:
    """The moment a text's days and times are counted from: when it was written if known, else the start."""
    written = _WRITTEN_AT.get()
    return start if written is None else written


class MatcherError(ValueError):
    """A matcher that cannot be compiled; the message names the operator and what is wrong."""


Check = Callable[[Any, Any, datetime], bool]
"""One operator's test, chosen when the matcher is compiled: ``check(prepared, value, start)``."""


Test = Callable[[Any, datetime], bool]
"""A compiled matcher's test: ``test(value, start)``."""


@dataclass(frozen=True, slots=True)
class Matcher:
    """A compiled matcher: ``test(value, start)`` says whether ``value`` is accepted."""

    operators: tuple[tuple[str, Any], ...] = ()
    fields: tuple[tuple[str, Matcher], ...] = ()
    test: Test = field(init=False, repr=False, compare=False)
    """Whether a value is accepted; relative times are resolved against the start. A function made for
    the matcher's shape when it is compiled (see :func:`_tester`): checks run it for every log entry and
    every item of the state, so it does only what this matcher needs.
    """

    def __post_init__(self) -> None:
        object.__setattr__(self, "test", _tester(self.operators, self.fields))

    def __reduce__(self) -> tuple[type[Matcher], tuple[Any, ...]]:
        # compiled again when unpickled: its test is a closure, which pickle cannot carry
        return Matcher, (self.operators, self.fields)

    @property
    def reads_days(self) -> bool:
        """Whether the matcher reads days or clock times in text (then when the text was written matters)."""
        for name, expected in self.operators:
            if name in _DAY_READERS:
                return True
            nested = expected if isinstance(expected, tuple) else (expected,)
            if any(isinstance(item, Matcher) and item.reads_days for item in nested):
                return True
        return any(matcher.reads_days for _, matcher in self.fields)

    @property
    def cost(self) -> int:
        """A rough rank of what a test costs, to try cheap matchers first where the order does not
        matter: 0 compares values, 1 reads times, 2 reads text or runs other matchers.
        """
        names = {name for name, _ in self.operators}
        if self.fields or not names <= _CHEAP_OPERATORS | TIME_OPERATORS:
            return 2
        return 0 if names <= _CHEAP_OPERATORS else 1

    def describe(self) -> str:
        """A short human reading, e.g. ``contains ['thursday']``."""
        if self.fields:
            return "{" + ", ".join(f"{key}: {matcher.describe()}" for key, matcher in self.fields) + "}"
        parts = []
        for name, expected in self.operators:
            if isinstance(expected, Matcher):
                parts.append(f"not ({expected.describe()})")
            elif name == "any_of":
                parts.append("any of (" + " | ".join(m.describe() for m in expected) + ")")
            elif isinstance(expected, re.Pattern):
                parts.append(f"{name} {expected.pattern!r}")
            elif isinstance(expected, time):
                parts.append(f"{name} {expected.strftime('%H:%M')}")
            else:
                shown = list(expected) if isinstance(expected, tuple) else expected
                parts.append(f"{name} {shown!r}")
        return " and ".join(parts)


def compile_matcher(raw: Any) -> Matcher:
    """Compile a matcher as written in a scenario file; :class:`MatcherError` says what is wrong.

    Compiled matchers are kept by the matcher's content: checks are evaluated again and again (every
    episode, every turn of a scenario that ends when met) from the same few specifications.
    """
    key = _frozen(raw)
    if key is None:
        return _compile(raw)
    known = _COMPILED.get(key)
    if known is None:
        known = _compile(raw)
        if len(_COMPILED) >= 16384:
            _COMPILED.clear()
        _COMPILED[key] = known
    return known


_COMPILED: dict[Any, Matcher] = {}


_SCALAR_TYPES = (str, int, float, bool, datetime, date, time, type(None))
_SCALARS = frozenset(_SCALAR_TYPES)
"""The types of the plain values matchers are made of (the exact types are told apart cheaply)."""


def _frozen(raw: Any) -> Any:
    """A hashable copy of ``raw`` that tells apart what compiles differently, or ``None`` if there is none.

    Computed for every matcher a scenario holds when it is loaded and when its checks are compiled: the
    common types are told by their exact type first, and a part without a copy ends the walk.
    """
    kind = type(raw)
    if kind in _SCALARS:
        return (kind.__name__, raw)  # the type too: True, 1 and 1.0 are equal but match differently
    if kind is dict or (kind is not list and isinstance(raw, Mapping)):
        items = []
        for key, value in raw.items():
            frozen = _frozen(value)
            if frozen is None:
                return None
            items.append((str(key), frozen))
        return ("map", tuple(items))
    if kind is list or isinstance(raw, list | tuple):
        parts = []
        for item in raw:
            frozen = _frozen(item)
            if frozen is None:
                return None
            parts.append(frozen)
        return ("list", tuple(parts))
    return (kind.__name__, raw) if isinstance(raw, _SCALAR_TYPES) else None


def _compile(raw: Any) -> Matcher:
    if isinstance(raw, Mapping):
        keys = [str(key) for key in raw]
        operators = [key for key in keys if key in OPERATORS]
        if operators and len(operators) != len(keys):
            others = [key for key in keys if key not in OPERATORS]
            raise MatcherError(
                f"mixes operators {operators} with other keys {others}; operators are "
                f"{', '.join(OPERATORS)} (to match fields of a mapping, list only field names)"
            )
        if not operators:
            if not keys:
                raise MatcherError("an empty mapping matches nothing useful; give a value or operators")
            return Matcher(fields=tuple((str(key), compile_matcher(value)) for key, value in raw.items()))
        return Matcher(operators=tuple(_compile_operator(str(k), v) for k, v in raw.items()))
    return Matcher(operators=(("equals", raw),))


def _compile_operator(name: str, value: Any) -> tuple[str, Any]:
    if name == "not":
        return name, compile_matcher(value)
    if name == "any_of":
        if not isinstance(value, list) or not value:
            raise MatcherError("'any_of' needs a non-empty list of matchers")
        return name, tuple(compile_matcher(item) for item in value)
    if name in ("contains", "contains_any", "affirms"):
        pieces = value if isinstance(value, list) else [value]
        if name == "contains_any" and not isinstance(value, list):
            raise MatcherError("'contains_any' needs a list of strings")
        if not pieces or not all(
            isinstance(p, str | int | float) and not isinstance(p, bool) and str(p).strip("* ")
            for p in pieces
        ):
            raise MatcherError(f"'{name}' needs a string or a list of non-empty strings, got {value!r}")
        return name, tuple(str(piece).casefold() for piece in pieces)
    if name == "declines":
        if not isinstance(value, bool):
            raise MatcherError(f"'declines' needs true or false, got {value!r}")
        return name, value
    if name == "mentions_clock":
        return name, _clock(value)
    if name == "regex":
        if not isinstance(value, str):
            raise MatcherError(f"'regex' needs a string, got {value!r}")
        try:
            return name, re.compile(value, re.IGNORECASE)
        except re.error as error:
            raise MatcherError(f"'regex' {value!r} is not a valid regular expression: {error}") from None
    if name in ("one_of", "same_set"):
        if not isinstance(value, list):
            raise MatcherError(f"'{name}' needs a list, got {value!r}")
        return name, tuple(value)
    if name in ("min", "max"):
        if isinstance(value, bool) or not isinstance(value, int | float):
            raise MatcherError(f"'{name}' needs a number, got {value!r}")
        return name, float(value)
    if name == "mentions_day" and isinstance(value, str) and _DAY_ONLY.fullmatch(value):
        value = f"{value.strip()} 00:00"  # a day alone: its clock time does not matter
    if name == "mentions_day" and isinstance(value, date) and not isinstance(value, datetime):
        value = f"{value.isoformat()} 00:00"  # YAML reads an unquoted 2025-07-05 as a date: a day alone
    if name in _TIME_OPERATORS:
        if not isinstance(value, str | datetime):
            raise MatcherError(f"'{name}' needs a time, got {value!r}")
        try:
            parse_time(value, datetime(2000, 1, 1, tzinfo=UTC))
        except TimeFormatError as error:
            raise MatcherError(f"'{name}': {error}") from None
        return name, value
    if name == "present":
        if not isinstance(value, bool):
            raise MatcherError(f"'present' needs true or false, got {value!r}")
        return name, value
    return name, value  # equals


def _operator_check(name: str, expected: Any) -> tuple[Check, Any, bool]:
    """One compiled operator's test, what it compares against, and whether it refuses ``None`` (every
    operator but ``equals``, ``not``, ``any_of`` and ``present``); see :data:`OPERATORS`.
    """
    if name == "equals":
        return (*_equals_check(expected), False)
    if name == "not":
        return _not, expected, False
    if name == "any_of":
        return _any_of, expected, False
    if name == "present":
        return _present, bool(expected), False
    if name in _READERS:
        return _reads, (_READERS[name], expected), True
    if name == "one_of":
        return _one_of, tuple(_equals_check(option) for option in expected), True
    if name == "same_set":
        return _same_set, _as_set(expected), True
    return _GIVEN_VALUE_CHECKS[name], expected, True


def _tester(operators: tuple[tuple[str, Any], ...], fields: tuple[tuple[str, Matcher], ...]) -> Test:
    """The test of a matcher of these operators or fields.

    A mapping of fields matches a mapping whose fields match, or a list holding such an item. Operators
    must all hold, and each but ``equals``, ``not``, ``any_of`` and ``present`` refuses ``None``: one
    operator's test is called directly, without a loop over one.
    """
    if fields:
        tests = tuple((key, matcher.test) for key, matcher in fields)

        def test_fields(value: Any, start: datetime) -> bool:
            if type(value) is not dict:  # the usual JSON mapping, told apart without asking Mapping
                if isinstance(value, list):  # a list holds such an item
                    return any(test_fields(item, start) for item in value)
                if not isinstance(value, Mapping):
                    return False
            return all(test(value.get(key), start) for key, test in tests)

        return test_fields
    checks = tuple(_operator_check(name, expected) for name, expected in operators)
    if len(checks) == 1:
        check, prepared, needs_value = checks[0]
        if not needs_value:
            return partial(check, prepared)

        def test_one(value: Any, start: datetime) -> bool:
            return value is not None and check(prepared, value, start)

        return test_one

    def test_all(value: Any, start: datetime) -> bool:
        for check, prepared, needs_value in checks:
            if (needs_value and value is None) or not check(prepared, value, start):
                return False
        return True

    return test_all


def _not(matcher: Matcher, value: Any, start: datetime) -> bool:
    return not matcher.test(value, start)


def _any_of(matchers: tuple[Matcher, ...], value: Any, start: datetime) -> bool:
    return any(matcher.test(value, start) for matcher in matchers)


def _present(wanted: bool, value: Any, start: datetime) -> bool:
    return (value is not None) is wanted


def _contains(pieces: tuple[str, ...], value: Any, start: datetime) -> bool:
    texts = _word_texts(value)
    for piece in pieces:  # loops, not all() and any(): they run for every text of every item checked
        found = meaning.word_finder(piece).found
        for text in texts:
            if found(text):
                break
        else:
            return False
    return True


def _contains_any(pieces: tuple[str, ...], value: Any, start: datetime) -> bool:
    texts = _word_texts(value)
    for piece in pieces:
        found = meaning.word_finder(piece).found
        for text in texts:
            if found(text):
                return True
    return False


def _word_texts(value: Any) -> list[str]:
    """The texts a value's words are sought in, read once for all the pieces sought: a list's items
    (nested lists too), each alone.
    """
    if type(value) is str:  # the usual case, without the walk
        return [meaning.normalise_quotes(value)]
    return [meaning.normalise_quotes(_text(item)) for item in _leaves(value)]


def _reads(reading: tuple[Callable[[str, Any, datetime], bool], Any], value: Any, start: datetime) -> bool:
    read, expected = reading
    return any(read(_text(item), expected, start) for item in _items(value))


def _regex(pattern: re.Pattern[str], value: Any, start: datetime) -> bool:
    return any(pattern.search(_text(item)) is not None for item in _items(value))


def _one_of(options: tuple[tuple[Check, Any], ...], value: Any, start: datetime) -> bool:
    return any(check(prepared, value, start) for check, prepared in options)


def _same_set(wanted: set[Any], value: Any, start: datetime) -> bool:
    return isinstance(value, Sequence) and not isinstance(value, str) and _as_set(value) == wanted


def _at_least(bound: float, value: Any, start: datetime) -> bool:
    number = _number(value)
    return number is not None and number >= bound


def _at_most(bound: float, value: Any, start: datetime) -> bool:
    number = _number(value)
    return number is not None and number <= bound


def _after(expected: str | datetime, value: Any, start: datetime) -> bool:
    moment = _time(value, start)
    return moment is not None and moment > _parse_time(expected, start)


def _from(expected: str | datetime, value: Any, start: datetime) -> bool:
    moment = _time(value, start)
    return moment is not None and moment >= _parse_time(expected, start)


def _before(expected: str | datetime, value: Any, start: datetime) -> bool:
    moment = _time(value, start)
    return moment is not None and moment < _parse_time(expected, start)


def _by(expected: str | datetime, value: Any, start: datetime) -> bool:
    moment = _time(value, start)
    return moment is not None and moment <= _parse_time(expected, start)


_GIVEN_VALUE_CHECKS: dict[str, Check] = {
    "contains": _contains,
    "contains_any": _contains_any,
    "regex": _regex,
    "min": _at_least,
    "max": _at_most,
    "after": _after,
    "from": _from,
    "before": _before,
    "by": _by,
}


def _items(value: Any) -> list[Any]:
    return value if isinstance(value, list) else [value]


def _leaves(value: Any) -> list[Any]:
    """The items of a list and of the lists in it; anything else alone."""
    if not isinstance(value, list):
        return [value]
    return [leaf for item in value for leaf in _leaves(item)]


def item_texts(value: Any, operator: str) -> list[str]:
    """The texts the text operator ``operator`` reads in ``value``, one per item it tries (to explain a
    verdict): a list's items, and for ``contains`` and ``contains_any`` the items of nested lists too.
    """
    items = _leaves(value) if operator in ("contains", "contains_any") else _items(value)
    return [_text(item) for item in items]


def _text(value: Any) -> str:
    """Text to search in: a mapping's values only (never its field names, so 'content' does not
    contain 'tent'), a list's items, anything else as written.
    """
    if isinstance(value, str):
        return value
    if isinstance(value, Mapping):
        return " ".join(_text(item) for item in value.values())
    if isinstance(value, list):
        return " ".join(_text(item) for item in value)
    return str(value)


def _clock(value: Any) -> time:
    """A clock time for ``mentions_clock``: ``"18:15"``, or any time (its clock time is taken)."""
    if isinstance(value, str):
        found = re.fullmatch(r"\s*(\d{1,2}):(\d{2})\s*", value)
        if found and int(found.group(1)) < 24 and int(found.group(2)) < 60:
            return time(int(found.group(1)), int(found.group(2)))
    if isinstance(value, str | datetime):
        try:
            return parse_time(value, datetime(2000, 1, 1, tzinfo=UTC)).time()
        except TimeFormatError:
            pass
    raise MatcherError(f"'mentions_clock' needs a clock time such as '18:15' or a time, got {value!r}")


def _read_affirms(text: str, pieces: tuple[str, ...], start: datetime) -> bool:
    return all(meaning.affirms(text, piece) for piece in pieces)


def _read_declines(text: str, wanted: bool, start: datetime) -> bool:
    return meaning.declines(text) is wanted


def _read_day(text: str, expected: Any, start: datetime) -> bool:
    return meaning.mentions_day(text, parse_time(expected, start).date(), reading_moment(start))


def _read_clock(text: str, expected: time, start: datetime) -> bool:
    return meaning.mentions_clock(text, expected, reading_moment(start))


def _read_moment(text: str, expected: Any, start: datetime) -> bool:
    return meaning.mentions_moment(text, parse_time(expected, start), reading_moment(start))


_READERS: dict[str, Callable[[str, Any, datetime], bool]] = {
    "affirms": _read_affirms,
    "declines": _read_declines,
    "mentions_day": _read_day,
    "mentions_clock": _read_clock,
    "mentions_time": _read_moment,
}


def _as_set(values: Sequence[Any]) -> set[Any]:
    return {v.strip().casefold() if isinstance(v, str) else repr(v) for v in values}


def _number(value: Any) -> float | None:
    if isinstance(value, bool):
        return None
    if isinstance(value, int | float):
        return float(value)
    if isinstance(value, str):
        try:
            number = float(value)
        except ValueError:
            return None
        return number if math.isfinite(number) else None
    return None


_parse_time = lru_cache(maxsize=16384)(parse_time)
""":func:`~pare.scenarios.times.parse_time`, remembered: the same scenario times and state values are
compared in every evaluation (a time that cannot be read is not remembered: it raises again)."""


def _time(value: Any, start: datetime) -> datetime | None:
    if type(value) is not str:  # a time in the state is text: told apart without two isinstance calls
        if isinstance(value, datetime):
            return value if value.tzinfo else value.replace(tzinfo=UTC)
        if not isinstance(value, str):
            return None
    try:
        return _parse_time(value, start)
    except TimeFormatError:
        return None


@lru_cache(maxsize=4096)
def _looks_like_time(text: str) -> bool:
    if is_relative_time(text):
        return True
    return bool(re.match(r"^\d{4}-\d{2}-\d{2}[T ]\d{2}:\d{2}", text.strip()))


def _equals_check(expected: Any) -> tuple[Check, Any]:
    """``equals``: times compare as times (whatever their format), numbers as numbers."""
    if isinstance(expected, datetime):
        # YAML reads an unquoted 2024-12-14T14:00:00Z as a datetime; the state holds text
        return _same_moment, (expected, expected if expected.tzinfo else expected.replace(tzinfo=UTC))
    if isinstance(expected, str) and _looks_like_time(expected):
        return _same_time, expected
    if isinstance(expected, int | float) and not isinstance(expected, bool):
        return _same_number, float(expected)
    return _same, expected


def _same(expected: Any, value: Any, start: datetime) -> bool:
    return bool(expected == value)


def _same_number(wanted: float, value: Any, start: datetime) -> bool:
    number = _number(value)
    return number is not None and number == wanted


def _same_moment(expected: tuple[datetime, datetime], value: Any, start: datetime) -> bool:
    written, moment = expected
    if isinstance(value, str | datetime):
        right = _time(value, start)
        return right is not None and right == moment
    return bool(written == value)


def _same_time(expected: str, value: Any, start: datetime) -> bool:
    if type(value) is str or isinstance(value, str | datetime):
        left, right = _time(expected, start), _time(value, start)
        if left is not None and right is not None:
            return left == right
    return bool(expected == value)
