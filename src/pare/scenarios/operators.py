"""The built-in matcher operators: one :class:`~pare.scenarios.matchers.Operator` record each.

A record says what the operator is written with, when it holds (the scenario guide's table and the
schema's description are made from these two), how its written value is checked and compiled, and how it
tests a value. :mod:`pare.scenarios.matchers` compiles and runs matchers from the records; importing
:mod:`pare.scenarios` registers these.

A new operator is one more record here (or a :func:`~pare.scenarios.matchers.register_operator` call
anywhere), then ``python scripts/operator_table.py`` to write its row into the guide.
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable, Mapping, Sequence
from datetime import UTC, date, datetime, time
from decimal import Decimal
from functools import lru_cache, partial
from typing import Any

from pare.scenarios import fact_details, meaning
from pare.scenarios.matchers import (
    Check,
    Chosen,
    Matcher,
    MatcherError,
    Operator,
    Test,
    compile_matcher,
    reading_moment,
    register_operator,
)
from pare.scenarios.numbers import NumberError, names_number, number_pattern
from pare.scenarios.text_reasons import (
    clock_label,
    declines_label,
    moment_label,
    pieces_label,
    regex_label,
    why_declines_differs,
    why_none_contained,
    why_not_affirmed,
    why_not_contained,
    why_not_found,
    why_not_mentioned,
)
from pare.scenarios.times import TimeFormatError, is_relative_time, parse_time


def _not(matcher: Matcher, value: Any, start: datetime) -> bool:
    return not matcher.test(value, start)


def _not_check(matcher: Matcher) -> Chosen:
    """``not``'s test: the matcher's text matches count only where the text puts them forward.

    A forbidden pattern must not fire on a clause that negates or passes over what it names: "not the
    regular oat drink" names the oat drink to turn it down. So under ``not``, a match of ``regex``,
    ``contains`` or ``contains_any`` (also inside ``any_of``) that begins in a clause
    :func:`~pare.scenarios.meaning.affirmed_clauses` drops does not count, unless it covers that clause's
    negation cue (a pattern seeking "can't make" still finds it). ``in_a_clause``, ``in_a_sentence`` and a
    ``not`` inside are their own readings, kept as they are.
    """
    affirmed = _affirmed_test(matcher)
    return Chosen(_not, matcher) if affirmed is None else Chosen(_not_affirmed, affirmed)


def _not_affirmed(affirmed: Test, value: Any, start: datetime) -> bool:
    return not affirmed(value, start)


def _affirmed_test(matcher: Matcher) -> Test | None:
    """``matcher``'s test counting only text matches in clauses that affirm (see :func:`_not_check`), or
    ``None`` when it has no text match to judge so. A ``not`` inside is read literally: it is an excuse
    that lifts the ban, whose words count wherever they are.
    """
    return _rebuilt_test(matcher, _affirmed_reader)


def _affirmed_reader(name: str, kept: Any) -> tuple[Test, bool] | None:
    reader = _AFFIRMED_READERS.get(name)
    if reader is not None:
        return partial(reader, kept), True
    return _literal_reader(name, kept)


def _literal_reader(name: str, kept: Any) -> tuple[Test, bool] | None:
    return (partial(_not, kept), False) if name == "not" else None


def _rebuilt_test(matcher: Matcher, reader: Callable[[str, Any], tuple[Test, bool] | None]) -> Test | None:
    """``matcher``'s test with the operators ``reader`` gives a test for (and whether it refuses a missing
    value) tested so, in it and in the options of its ``any_of``; ``None`` when there are none.
    """
    if matcher.fields:
        return None
    parts: list[tuple[Test, bool]] = []  # each operator's test, and whether it refuses a missing value
    changed = False
    for name, kept in matcher.operators:
        replaced = reader(name, kept)
        if replaced is not None:
            parts.append(replaced)
            changed = True
        elif name == "any_of":
            tests = [_rebuilt_test(option, reader) for option in kept]
            changed = changed or any(test is not None for test in tests)
            options = tuple(
                option.test if test is None else test for option, test in zip(kept, tests, strict=True)
            )
            parts.append((partial(_any_test, options), False))
        else:
            parts.append((Matcher(operators=((name, kept),)).test, False))
    if not changed:
        return None

    def test(value: Any, start: datetime) -> bool:
        return all((value is not None or not refuses) and part(value, start) for part, refuses in parts)

    return test


def _any_test(tests: tuple[Test, ...], value: Any, start: datetime) -> bool:
    return any(test(value, start) for test in tests)


def _put_forward(pattern: re.Pattern[str], text: str) -> bool:
    """Whether ``pattern`` matches ``text`` where the text puts it forward: a match beginning in a clause
    that affirms, or covering the negation cue of the clause it begins in.
    """
    found = pattern.search(text)
    if found is None:
        return False
    spans = meaning.clause_spans(text)
    if all(span.affirmed for span in spans):  # the usual text: nothing negated, every match counts
        return True
    while found is not None:
        begin, end = found.span()
        clause = next((span for span in spans if span.holds(begin, end)), None)
        if clause is None or clause.affirmed or clause.covers_cue(begin, end):
            return True
        found = pattern.search(text, begin + 1)  # a later match may begin in a clause that affirms
    return False


def _regex_affirmed(pattern: re.Pattern[str], value: Any, start: datetime) -> bool:
    return any(_put_forward(pattern, _text(item)) for item in _items(value))


def _word_put_forward(piece: str, text: str) -> bool:
    return _put_forward(meaning.word_pattern(meaning.normalise_quotes(piece)), text)


def _contains_affirmed(pieces: tuple[str, ...], value: Any, start: datetime) -> bool:
    texts = _word_texts(value)
    return all(any(_word_put_forward(piece, text) for text in texts) for piece in pieces)


def _contains_any_affirmed(pieces: tuple[str, ...], value: Any, start: datetime) -> bool:
    texts = _word_texts(value)
    return any(_word_put_forward(piece, text) for piece in pieces for text in texts)


_AFFIRMED_READERS: dict[str, Callable[[Any, Any, datetime], bool]] = {
    "regex": _regex_affirmed,
    "contains": _contains_affirmed,
    "contains_any": _contains_any_affirmed,
}
"""The text operators whose matches ``not`` judges by the clause they begin in."""


def _in_some(split: Callable[[str], list[str]], test: Test, value: Any, start: datetime) -> bool:
    """Whether one part of the value's text (a clause, a sentence) meets the matcher's ``test`` on its own."""
    return any(test(part, start) for item in _items(value) for part in split(_text(item)))


def _part_test(matcher: Matcher) -> Test:
    """The test ``in_a_clause`` and ``in_a_sentence`` give each part: the matcher's, with a ``not`` inside
    read literally. A ``not`` there sets the part aside for a word it holds (``not: {contains_any:
    [personal]}`` in "not claiming Annecy, that was personal"): the part is already chosen, so its words
    count wherever they are.
    """
    return _literal_test(matcher)


def _options_tests(matchers: tuple[Matcher, ...]) -> tuple[Test, ...]:
    """The tests ``any_of`` tries: each option's, but an option that is a ``not`` alone read literally.

    Such an option is one way for the value to be so ("or it does not mention the trip"): the words of
    its ``not`` count wherever they are. A ``not`` beside other operators in an option bans a pattern in
    what they find ("names the energy company, not the bill"), as it does outside (see :func:`_not_check`).
    """
    return tuple(
        _literal_test(matcher) if [name for name, _ in matcher.operators] == ["not"] else matcher.test
        for matcher in matchers
    )


def _literal_test(matcher: Matcher) -> Test:
    """``matcher``'s test with a ``not`` in it (or in the options of its ``any_of``) read literally."""
    literal = _rebuilt_test(matcher, _literal_reader)
    return matcher.test if literal is None else literal


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


def _reader(read: Callable[[str, Any, datetime], bool]) -> Check:
    """The test of an operator that reads each item's text with ``read(text, expected, start)``."""

    def test(expected: Any, value: Any, start: datetime) -> bool:
        return any(read(_text(item), expected, start) for item in _items(value))

    return test


def _regex(pattern: re.Pattern[str], value: Any, start: datetime) -> bool:
    return any(pattern.search(_text(item)) is not None for item in _items(value))


def _number_written(value: Any) -> str:
    if not isinstance(value, str | int) or isinstance(value, bool):
        raise MatcherError(
            f"'mentions_number' needs a number written as text ('07700 900742'), got {value!r}"
        )
    try:
        number_pattern(str(value))
    except NumberError as error:
        raise MatcherError(f"'mentions_number' {error}") from None
    return str(value)


def _read_number(text: str, written: str, start: datetime) -> bool:
    return names_number(text, written)


def _one_of(options: tuple[Chosen, ...], value: Any, start: datetime) -> bool:
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


def _read_negated(text: str, wanted: bool, start: datetime) -> bool:
    return any(meaning.is_negated(clause) for clause in meaning.clauses(text)) is wanted


def _read_declines(text: str, wanted: bool, start: datetime) -> bool:
    if not wanted:  # an answer that does not refuse, and is one: a hedge neither refuses nor agrees
        return not meaning.declines(text) and meaning.hedge(text) is None
    return meaning.declines(text)


def _read_day(text: str, expected: Any, start: datetime) -> bool:
    return meaning.mentions_day(text, parse_time(expected, start).date(), reading_moment(start))


def _read_clock(text: str, expected: time, start: datetime) -> bool:
    return meaning.mentions_clock(text, expected, reading_moment(start))


def _read_moment(text: str, expected: Any, start: datetime) -> bool:
    return meaning.mentions_moment(text, parse_time(expected, start), reading_moment(start))


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


def _equals_check(expected: Any) -> Chosen:
    """``equals``: times compare as times (whatever their format), numbers as numbers."""
    if isinstance(expected, datetime):
        # YAML reads an unquoted 2024-12-14T14:00:00Z as a datetime; the state holds text
        return Chosen(_same_moment, (expected, expected if expected.tzinfo else expected.replace(tzinfo=UTC)))
    if isinstance(expected, str) and _looks_like_time(expected):
        return Chosen(_same_time, expected)
    if isinstance(expected, int | float) and not isinstance(expected, bool):
        return Chosen(_same_number, float(expected))
    return Chosen(_same, expected)


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


# -- what operators are written with ---------------------------------------------------------------------
def _pieces(name: str, value: Any) -> tuple[str, ...]:
    """Words sought in text: a string or a list of non-empty strings (numbers too), casefolded."""
    pieces = value if isinstance(value, list) else [value]
    if name == "contains_any" and not isinstance(value, list):
        raise MatcherError("'contains_any' needs a list of strings")
    if not pieces or not all(
        isinstance(p, str | int | float) and not isinstance(p, bool) and str(p).strip("* ") for p in pieces
    ):
        raise MatcherError(f"'{name}' needs a string or a list of non-empty strings, got {value!r}")
    return tuple(str(piece).casefold() for piece in pieces)


def _flag(name: str, value: Any) -> bool:
    if not isinstance(value, bool):
        raise MatcherError(f"'{name}' needs true or false, got {value!r}")
    return value


def _pattern(value: Any) -> re.Pattern[str]:
    if not isinstance(value, str):
        raise MatcherError(f"'regex' needs a string, got {value!r}")
    try:
        return re.compile(value, re.IGNORECASE)
    except re.error as error:
        raise MatcherError(f"'regex' {value!r} is not a valid regular expression: {error}") from None


def _listed(name: str, value: Any) -> tuple[Any, ...]:
    if not isinstance(value, list):
        raise MatcherError(f"'{name}' needs a list, got {value!r}")
    return tuple(value)


def _bound(name: str, value: Any) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise MatcherError(f"'{name}' needs a number, got {value!r}")
    return float(value)


def _moment(name: str, value: Any) -> str | datetime:
    """A time as written (absolute, or relative to the start), checked: it is read at each test."""
    if not isinstance(value, str | datetime):
        raise MatcherError(f"'{name}' needs a time, got {value!r}")
    try:
        parse_time(value, datetime(2000, 1, 1, tzinfo=UTC))
    except TimeFormatError as error:
        raise MatcherError(f"'{name}': {error}") from None
    return value


def _day(value: Any) -> str | datetime:
    """A day for ``mentions_day``: a day alone (``day+3``, a date) is read at 00:00, a time as its day."""
    if isinstance(value, str) and _DAY_ONLY.fullmatch(value):
        value = f"{value.strip()} 00:00"  # a day alone: its clock time does not matter
    if isinstance(value, date) and not isinstance(value, datetime):
        value = f"{value.isoformat()} 00:00"  # YAML reads an unquoted 2025-07-05 as a date: a day alone
    return _moment("mentions_day", value)


def _matchers(value: Any) -> tuple[Matcher, ...]:
    if not isinstance(value, list) or not value:
        raise MatcherError("'any_of' needs a non-empty list of matchers")
    return tuple(compile_matcher(item) for item in value)


def _one(value: Any) -> Sequence[Any]:
    return [value]


def _alternatives(value: Any) -> Sequence[Any]:
    return value if isinstance(value, list) else []


_DAY_ONLY = re.compile(r"\s*day\s*([+-]\s*\d+)?\s*")


# -- only_clocks, only_days, only_amounts: a text names no value of a kind but the ones listed --------------
def _allowed_values(name: str, value: Any) -> list[Any]:
    if not isinstance(value, list) or not value:
        raise MatcherError(f"'{name}' needs a non-empty list of the values a right text may name")
    return value


def _clocks(value: Any) -> tuple[tuple[time, time], ...]:
    """The spans ``only_clocks`` allows: a clock time ('17:15') or a span of them ('14:00-18:00')."""
    spans = set()
    for item in _allowed_values("only_clocks", value):
        first, dash, last = item.partition("-") if isinstance(item, str) else (item, "", "")
        start = _clock(first.strip() if isinstance(first, str) else first)
        end = _clock(last.strip()) if dash else start
        if end < start:
            raise MatcherError(f"'only_clocks' span {item!r} ends before it starts")
        spans.add((start, end))
    return tuple(sorted(spans))


def _span(span: tuple[time, time]) -> str:
    first, last = span
    return first.strftime("%H:%M") + ("" if first == last else "-" + last.strftime("%H:%M"))


def _days(value: Any) -> tuple[str | datetime, ...]:
    return tuple(_day(item) for item in _allowed_values("only_days", value))


def _amounts(value: Any) -> tuple[Decimal, ...]:
    found: set[Decimal] = set()
    for item in _allowed_values("only_amounts", value):
        text = str(item) if isinstance(item, int | float | str) and not isinstance(item, bool) else None
        amounts = fact_details.stated_amounts(f"£{text.lstrip('£$€')}") if text is not None else ()
        if len(amounts) != 1:
            raise MatcherError(f"'only_amounts' needs amounts such as '14.99' or '£14.99', got {item!r}")
        found |= {amount for amount, _ in amounts}
    return tuple(sorted(found))


def _allows_amount(amount: Decimal, rough: bool, allowed: frozenset[Decimal]) -> bool:
    """Whether ``amount`` is one of ``allowed``, or near one (2 %) when said to be rough."""
    if amount.normalize() in allowed:
        return True
    return rough and any(abs(amount - value) <= abs(value) * Decimal("0.02") for value in allowed)


def _allowed_days(days: tuple[str | datetime, ...], start: datetime) -> frozenset[date]:
    return frozenset(parse_time(day, start).date() for day in days)


def _read_only_clocks(text: str, allowed: tuple[tuple[time, time], ...], start: datetime) -> bool:
    return not meaning.stray_clocks(text, allowed, reading_moment(start))


def _read_only_days(text: str, allowed: tuple[str | datetime, ...], start: datetime) -> bool:
    return not meaning.stray_days(text, _allowed_days(allowed, start), reading_moment(start))


def _stray_amounts(text: str, allowed: tuple[Decimal, ...]) -> list[Decimal]:
    given = frozenset(value.normalize() for value in allowed)
    return [
        amount
        for clause in meaning.affirmed_clauses(text)
        for amount, rough in fact_details.stated_amounts(clause)
        if not _allows_amount(amount, rough, given)
    ]


def _read_only_amounts(text: str, allowed: tuple[Decimal, ...], start: datetime) -> bool:
    return not _stray_amounts(text, allowed)


def _why_stray_clocks(text: str, allowed: tuple[tuple[time, time], ...], start: datetime) -> str:
    stray = meaning.stray_clocks(text, allowed, reading_moment(start))
    named = ", ".join("/".join(clock.strftime("%H:%M") for clock in sorted(m.times)) for m in stray)
    return f"the text names {named} in a clause without negation, which the rule does not allow"


def _why_stray_days(text: str, allowed: tuple[str | datetime, ...], start: datetime) -> str:
    stray = meaning.stray_days(text, _allowed_days(allowed, start), reading_moment(start))
    named = ", ".join("/".join(day.strftime("%a %-d %b") for day in sorted(m.days)) for m in stray)
    return f"the text names {named} in a clause without negation, which the rule does not allow"


def _why_stray_amounts(text: str, allowed: tuple[Decimal, ...], start: datetime) -> str:
    named = ", ".join(f"{amount:f}" for amount in _stray_amounts(text, allowed))
    return f"the text states the amount {named} in a clause without negation, which the rule does not allow"


def _listed_label(name: str, shown: Callable[[Any], str]) -> Callable[[Any, datetime], str]:
    return lambda kept, start: f"{name} [{', '.join(shown(value) for value in kept)}]"


_TIME_WRITTEN = "a time, absolute or relative to the start"


# -- the operators ---------------------------------------------------------------------------------------
for _operator in (
    Operator(
        "equals",
        "a value",
        "is equal to it (times compare as times, whatever their format)",
        _same,
        prepare=_equals_check,
        refuses_none=False,
    ),
    Operator(
        "contains",
        "a string or a list of strings",
        "contains the string, or every string of the list, as whole words, case-insensitively ('wed' is "
        "not found in 'reviewed'; a '*' after a word lets that word go on: 'view*', 'drop* us'); of a list "
        "value, "
        "some element does",
        _contains,
        partial(_pieces, "contains"),
        reads="text",
        explain=why_not_contained,
        label=partial(pieces_label, "contains"),
    ),
    Operator(
        "contains_any",
        "a list of strings",
        "contains at least one of the strings, as whole words, case-insensitively",
        _contains_any,
        partial(_pieces, "contains_any"),
        reads="text",
        explain=why_none_contained,
        label=partial(pieces_label, "contains_any"),
    ),
    Operator(
        "affirms",
        "a string or a list of strings",
        "mentions every string in a clause without negation ('Thursday works' affirms thursday; "
        "'Thursday does not work' does not)",
        _reader(_read_affirms),
        partial(_pieces, "affirms"),
        reads="text",
        explain=why_not_affirmed,
        label=partial(pieces_label, "affirms"),
    ),
    Operator(
        "declines",
        "true or false",
        "refuses, cancels or says something does not work, read as a whole ('Can't, sorry', 'No thanks', "
        "'I'll pass', 'no need, I have a taxi'), for true; does not, for false. Turning one option down "
        "and taking up another in a later clause ('12:00 won't work, so could I have 14:00?') is a "
        "counter-offer, not a refusal. False also needs a firm answer: a hedged one ('probably', 'I'll "
        "confirm later', 'can I let you know tomorrow?', with no firm 'yes' or 'count me in' beside it) "
        "neither refuses nor agrees, so it meets neither",
        _reader(_read_declines),
        partial(_flag, "declines"),
        reads="text",
        explain=why_declines_differs,
        label=declines_label,
    ),
    Operator(
        "negated",
        "true or false",
        "has a clause with a negation cue ('not', 'no longer', 'ruled out'; friendly ones such as 'no "
        "problem' do not count), for true; has none, for false. Inside `in_a_clause` it reads that "
        "clause: `{in_a_clause: {contains: again, negated: false}}`",
        _reader(_read_negated),
        partial(_flag, "negated"),
        reads="text",
    ),
    Operator(
        "mentions_day",
        "a day ('day+3', a date) or a time (its day)",
        "names that day: 'Thu', '20 March', 'tomorrow', '20/03'; mentions in negated clauses do not count",
        _reader(_read_day),
        _day,
        reads="text",
        reads_days=True,
        explain=why_not_mentioned,
        label=partial(moment_label, "mentions_day"),
    ),
    Operator(
        "mentions_clock",
        "a clock time ('18:15') or a time (its clock time)",
        "names that clock time: '6:15pm', '18.15', '18h15', 'at 6'",
        _reader(_read_clock),
        _clock,
        reads="text",
        reads_days=True,
        explain=why_not_mentioned,
        label=clock_label,
    ),
    Operator(
        "mentions_time",
        "a time",
        "names that day together with that clock time, in one sentence or as the text's only day and only "
        "time: 'Thursday at 6.15pm'",
        _reader(_read_moment),
        partial(_moment, "mentions_time"),
        reads="text",
        reads_days=True,
        explain=why_not_mentioned,
        label=partial(moment_label, "mentions_time"),
    ),
    Operator(
        "only_clocks",
        "a list of clock times or spans ('17:15', '14:00-18:00')",
        "names no clock time but these, in clauses without negation ('at 6' may be 06:00 or 18:00: one "
        "listed reading is enough; both ends of a range it names count); a text naming none holds",
        _reader(_read_only_clocks),
        _clocks,
        reads="text",
        reads_days=True,
        describe=lambda kept: f"only_clocks [{', '.join(_span(span) for span in kept)}]",
        explain=_why_stray_clocks,
        label=_listed_label("only_clocks", _span),
    ),
    Operator(
        "only_days",
        "a list of days ('day+3', a date)",
        "names no day but these ('Thu', '20 March', 'tomorrow', 'last Saturday', read as of when the text "
        "was written), in clauses without negation; a text naming none holds",
        _reader(_read_only_days),
        _days,
        reads="text",
        reads_days=True,
        describe=lambda kept: (
            "only_days [" + ", ".join(str(day).removesuffix(" 00:00") for day in kept) + "]"
        ),
        explain=_why_stray_days,
        label=_listed_label("only_days", lambda day: str(day).removesuffix(" 00:00")),
    ),
    Operator(
        "only_amounts",
        "a list of amounts ('14.99', '120')",
        "states no money amount but these ('14.99 pounds', '$1,200', '1.2k'), by value, in clauses without "
        "negation ('about $59' may be up to 2 % off one); a text stating none holds",
        _reader(_read_only_amounts),
        _amounts,
        reads="text",
        describe=lambda kept: f"only_amounts [{', '.join(f'{amount:f}' for amount in kept)}]",
        explain=_why_stray_amounts,
        label=_listed_label("only_amounts", lambda amount: f"{amount:f}"),
    ),
    Operator(
        "regex",
        "a regular expression",
        "matches the regular expression somewhere (case-insensitive; raw text, no word rules)",
        _regex,
        _pattern,
        reads="text",
        explain=why_not_found,
        label=regex_label,
    ),
    Operator(
        "mentions_number",
        "a phone number or another number of 3 or more digits, as text",
        "names that number, digit by digit whatever its grouping: '07700 900742' is found in "
        "'0770 090 0742', '07700-900-742' and '+44 7700 900742' (a '+' and a country code stand for a "
        "leading 0), not in '07700 9007421'",
        _reader(_read_number),
        _number_written,
        reads="text",
        explain=lambda text, written, start: "no number in the text has those digits in that order",
    ),
    Operator(
        "one_of",
        "a list of values",
        "equals one of the values",
        _one_of,
        partial(_listed, "one_of"),
        prepare=lambda options: tuple(_equals_check(option) for option in options),
    ),
    Operator(
        "same_set",
        "a list",
        "is a list with the same elements in any order (text compared case-insensitively)",
        _same_set,
        partial(_listed, "same_set"),
        prepare=_as_set,
        reads="list",
    ),
    Operator(
        "min", "a number", "is a number at least this", _at_least, partial(_bound, "min"), reads="number"
    ),
    Operator("max", "a number", "is a number at most this", _at_most, partial(_bound, "max"), reads="number"),
    Operator(
        "after",
        _TIME_WRITTEN,
        "is a time strictly after it: the bound itself fails",
        _after,
        partial(_moment, "after"),
        reads="time",
    ),
    Operator(
        "from",
        _TIME_WRITTEN,
        "is a time at or after it: the bound itself holds",
        _from,
        partial(_moment, "from"),
        reads="time",
    ),
    Operator(
        "before",
        _TIME_WRITTEN,
        "is a time strictly before it: the bound itself fails",
        _before,
        partial(_moment, "before"),
        reads="time",
    ),
    Operator(
        "by",
        _TIME_WRITTEN,
        "is a time at or before it: the bound itself holds",
        _by,
        partial(_moment, "by"),
        reads="time",
    ),
    Operator(
        "present",
        "true or false",
        "is given (true) or is missing or null (false)",
        _present,
        partial(_flag, "present"),
        refuses_none=False,
    ),
    Operator(
        "not",
        "a matcher",
        "does not match it. A `regex`, `contains` or `contains_any` inside (or in an `any_of` inside) "
        "does not count a match that begins in a clause negating or passing over what it names: "
        "`{not: {contains: oat}}` holds for 'the barista one, not the regular oat drink'; a match that "
        "covers the clause's own cue still counts (`{not: {regex: \"can't make\"}}` finds 'I can't make "
        "it'). A `not` inside `in_a_clause` or `in_a_sentence`, or that is a whole `any_of` option, sets "
        "an exception aside and counts its words anywhere",
        _not,
        compile_matcher,
        prepare=_not_check,
        reads="matchers",
        refuses_none=False,
        nested=_one,
        describe=lambda matcher: f"not ({matcher.describe()})",
    ),
    Operator(
        "in_a_clause",
        "a matcher",
        "has a clause that meets it on its own (clauses as negation reads them: a sentence is cut at "
        "commas, colons, dashes, 'but', 'if', and a reason or consequence with its own subject, 'as the "
        "garage can't...', 'so it won't...'): `{in_a_clause: {contains: harbour, not: {contains_any: "
        "[skipped, left out]}}}` finds Harbour put forward without an excuse in the same clause; negated "
        "clauses are tested too, so put `affirms` inside for words that must not be negated",
        partial(_in_some, meaning.clauses),
        compile_matcher,
        prepare=_part_test,
        reads="matchers",
        nested=_one,
        describe=lambda matcher: f"in_a_clause ({matcher.describe()})",
    ),
    Operator(
        "in_a_sentence",
        "a matcher",
        "has a sentence that meets it on its own (`{in_a_sentence: {affirms: [promise*], mentions_day: "
        "day+3}}`: the promise and the day in one sentence)",
        partial(_in_some, meaning.sentences),
        compile_matcher,
        prepare=_part_test,
        reads="matchers",
        nested=_one,
        describe=lambda matcher: f"in_a_sentence ({matcher.describe()})",
    ),
    Operator(
        "any_of",
        "a list of matchers",
        "matches at least one of them (`{any_of: [{present: false}, {equals: user-laura}]}`: missing or "
        "Laura)",
        _any_test,
        _matchers,
        prepare=_options_tests,
        reads="matchers",
        refuses_none=False,
        nested=_alternatives,
        describe=lambda matchers: "any of (" + " | ".join(m.describe() for m in matchers) + ")",
    ),
):
    register_operator(_operator)
