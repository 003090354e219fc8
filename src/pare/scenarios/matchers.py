"""Value matchers: how a check says which argument values or state values it accepts.

Written in YAML as a plain value (``email-12``: equal to it), or as a mapping of operators that must all
hold::

    content: {contains: [thursday, "3"]}         # whole words, case-insensitive, every piece
    content: {affirms: thursday, mentions_time: day+2 18:15}   # read for meaning, not wording
    recipients: {same_set: [bob@x.org, ann@x.org]}
    start_datetime: {from: day+1 09:00, before: day+1 12:00}   # 09:00 in, 12:00 out (``by`` keeps it)
    updates: {start_datetime: day+1 10:00}        # a mapping of fields: each listed field must match

A mapping whose keys are not operators matches a mapping value field by field (unlisted fields are
ignored), or a list value holding at least one such mapping.

This module compiles and runs matchers. Each operator is one :class:`Operator` record in
:data:`OPERATORS` (the built-in ones are in :mod:`pare.scenarios.operators`): what it is written with, when
it holds, how its value is compiled and how it tests a value. The schema's description of matchers, the
scenario guide's table (``scripts/operator_table.py``) and the checks on which fields an operator applies
to are read from the records, so a new operator is one :func:`register_operator` call.
"""

from __future__ import annotations

import re
from collections.abc import Callable, Iterator, Mapping, Sequence
from contextlib import contextmanager
from contextvars import ContextVar
from dataclasses import dataclass, field
from datetime import date, datetime, time
from functools import partial
from typing import Any, Literal, NamedTuple

Reads = Literal["value", "number", "time", "text", "list", "matchers"]
"""What an operator reads in a value: it compares the value as a whole (``value``), reads it as a number,
a time, text (the words of a text, or of a list's or a record's texts) or a list, or runs the matchers it
holds (``not``, ``any_of``). Which fields it applies to (:mod:`pare.scenarios.kinds`), whether a check
with it judges free text, and what its test costs follow from this."""

_COST: dict[Reads, int] = {"value": 0, "number": 0, "time": 1, "text": 2, "list": 2, "matchers": 2}


def _as_written(value: Any) -> Any:
    return value


class Chosen(NamedTuple):
    """What an operator's ``prepare`` may return to choose its test by the compiled value (``equals``
    compares times as times and numbers as numbers): the test, and what it compares against.
    """

    check: Check
    prepared: Any


@dataclass(frozen=True, slots=True)
class Operator:
    """One matcher operator: everything about it is here, and every table of operators (the schema's
    description, the guide's table, which fields it applies to) is read from :data:`OPERATORS`.

    Adding an operator is one :func:`register_operator` call with one of these.
    """

    name: str
    """Its key in a matcher (``contains``)."""
    takes: str
    """What it is written with (``a string or a list of strings``)."""
    doc: str
    """When it holds, completing "holds when the value ..." (``contains the string, ...``)."""
    test: Check
    """Whether a value is accepted: ``test(prepared, value, start)``, relative times against the start."""
    compile: Callable[[Any], Any] = _as_written
    """The written value checked (a :class:`MatcherError` saying what is wrong) and read into what the
    compiled matcher keeps and shows: ``contains`` keeps its pieces casefolded."""
    prepare: Callable[[Any], Any] | None = None
    """The kept value made into what ``test`` takes, once, when the matcher is compiled (``same_set``
    makes a set); a :class:`Chosen` chooses the test too. Default: the kept value itself."""
    reads: Reads = "value"
    """What it reads in a value (:data:`Reads`)."""
    refuses_none: bool = True
    """A missing value fails without asking ``test`` (``equals``, ``present``, ``not``, ``any_of`` ask)."""
    reads_days: bool = False
    """It reads days or clock times in text, which are counted from when the text was written."""
    nested: Callable[[Any], Sequence[Any]] | None = None
    """The matchers written inside it (``not``, ``any_of``), for the checks that look into them."""
    describe: Callable[[Any], str] | None = None
    """How it reads with its kept value, when ``<name> <value>`` does not say it (``not (...)``)."""
    explain: Callable[[str, Any, datetime], str] | None = None
    """Why one text of a value fails it, ``explain(text, kept, start)``, for an operator that reads text
    (read again only to explain a failing check; without it, a failure shows what the value was)."""
    label: Callable[[Any, datetime], str] | None = None
    """How an explanation names it with its kept value, relative days resolved (default: ``describe``)."""

    @property
    def cost(self) -> int:
        """A rough rank of what its test costs: 0 compares values, 1 reads times, 2 reads text or runs
        other matchers (cheap matchers are tried first where the order does not matter).
        """
        return _COST[self.reads]


OPERATORS: dict[str, Operator] = {}
"""Every matcher operator by name, in the order the schema and the guide list them."""


def register_operator(operator: Operator) -> None:
    """Make ``operator`` available in every matcher (and in the schema's description and the guide's table).

    Raises ``ValueError`` when the name is taken, or is one a mapping of fields could not tell apart.
    """
    if operator.name in OPERATORS:
        raise ValueError(f"matcher operator '{operator.name}' is already registered")
    if not operator.name.isidentifier() or operator.name.startswith("_"):
        raise ValueError(f"a matcher operator's name is a word, not '{operator.name}'")
    OPERATORS[operator.name] = operator
    _COMPILED.clear()  # a mapping with this key read as fields before now reads as the operator


def unregister_operator(name: str) -> Operator:
    """Remove the operator ``name`` and return it (for tests that register one of their own)."""
    operator = OPERATORS.pop(name)
    _COMPILED.clear()
    return operator


def reads_text(name: str) -> bool:
    """Whether ``name`` is an operator that reads text (it applies to text, or lists and records of text)."""
    operator = OPERATORS.get(name)
    return operator is not None and operator.reads == "text"


_WRITTEN_AT: ContextVar[datetime | None] = ContextVar("written_at", default=None)
"""When the text being read was written, where the caller knows it (see :func:`written_at`)."""


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
            if OPERATORS[name].reads_days:
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
        if self.fields:
            return 2
        return max((OPERATORS[name].cost for name, _ in self.operators), default=0)

    def describe(self) -> str:
        """A short human reading, e.g. ``contains ['thursday']``."""
        if self.fields:
            return "{" + ", ".join(f"{key}: {matcher.describe()}" for key, matcher in self.fields) + "}"
        parts = []
        for name, expected in self.operators:
            describe = OPERATORS[name].describe
            if describe is not None:
                parts.append(describe(expected))
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
    return name, OPERATORS[name].compile(value)


def _operator_check(name: str, expected: Any) -> tuple[Check, Any, bool]:
    """One compiled operator's test, what it compares against, and whether it refuses ``None``."""
    operator = OPERATORS[name]
    prepared = expected if operator.prepare is None else operator.prepare(expected)
    if isinstance(prepared, Chosen):
        return prepared.check, prepared.prepared, operator.refuses_none
    return operator.test, prepared, operator.refuses_none


def _tester(operators: tuple[tuple[str, Any], ...], fields: tuple[tuple[str, Matcher], ...]) -> Test:
    """The test of a matcher of these operators or fields.

    A mapping of fields matches a mapping whose fields match, or a list holding such an item. Operators
    must all hold, and those that refuse ``None`` (:attr:`Operator.refuses_none`) fail on it without
    being asked: one operator's test is called directly, without a loop over one.
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
