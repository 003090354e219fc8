from __future__ import annotations

from collections.abc import Mapping
from datetime import UTC, date, datetime, time
from types import MappingProxyType
from typing import Any

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from pare.scenarios.matchers import MatcherError, _frozen, compile_matcher

START = datetime(2025, 3, 3, 9, 0, tzinfo=UTC)


def holds(raw: Any, value: Any) -> bool:
    return compile_matcher(raw).test(value, START)


def test_plain_value_is_equality() -> None:
    assert holds("email-1", "email-1")
    assert not holds("email-1", "email-2")
    assert holds(3, 3.0) and holds(3, "3")
    assert holds(["a", "b"], ["a", "b"]) and not holds(["a", "b"], ["b", "a"])


def test_times_compare_as_times_whatever_the_format() -> None:
    assert holds("day+1 10:00", "2025-03-04T10:00:00+00:00")
    assert holds("day+1 10:00", "2025-03-04 10:00")
    assert holds("2025-03-04T10:00:00Z", "2025-03-04T11:00:00+01:00")
    assert not holds("day+1 10:00", "2025-03-04 10:30")


@pytest.mark.parametrize(
    ("raw", "value", "expected"),
    [
        ({"contains": "Thursday"}, "see you THURSDAY at 8", True),
        ({"contains": ["thursday", "8"]}, "thursday at 8", True),
        ({"contains": ["thursday", "9"]}, "thursday at 8", False),
        ({"contains": "bob@x.org"}, ["ann@x.org", "bob@x.org"], True),
        ({"contains_any": ["2pm", "14:00"]}, "at 14:00 sharp", True),
        ({"contains_any": ["2pm", "14:00"]}, "at noon", False),
        ({"regex": r"\b8(:00)?\s*am\b"}, "Thursday 8 AM works", True),
        ({"one_of": ["a", "b"]}, "b", True),
        ({"one_of": ["a", "b"]}, "c", False),
        ({"same_set": ["Bob", "ann"]}, ["ANN", "bob"], True),
        ({"same_set": ["Bob", "ann"]}, ["ann"], False),
        ({"same_set": ["Bob"]}, "Bob", False),
        ({"min": 2, "max": 5}, 3, True),
        ({"min": 2, "max": 5}, "6", False),
        ({"max": 100}, "cheap", False),
        ({"after": "day+1 00:00", "before": "day+1 23:59"}, "2025-03-04T12:00:00Z", True),
        ({"after": "day+1 00:00"}, "2025-03-03T12:00:00Z", False),
        ({"after": "+0m"}, "not a time", False),
        ({"present": True}, "x", True),
        ({"present": True}, None, False),
        ({"present": False}, None, True),
        ({"not": {"contains": "cancel"}}, "confirmed", True),
        ({"not": "ev1"}, "ev1", False),
        ({"any_of": [{"contains": "2pm"}, {"regex": "14[:.]00"}]}, "14.00", True),
        ({"start": "day+1 10:00"}, {"start": "2025-03-04T10:00:00Z", "title": "x"}, True),
        ({"start": "day+1 10:00"}, "not a mapping", False),
        (
            {"item_id": "a", "quantity": 2},
            [{"item_id": "b", "quantity": 2}, {"item_id": "a", "quantity": 2}],
            True,
        ),
        ({"item_id": "a", "quantity": 2}, [{"item_id": "a", "quantity": 1}], False),
        ({"contains": "x"}, None, False),
        ({"contains": "tent"}, [{"content": "hello", "sender_id": "u1"}], False),
        ({"contains": "hello"}, [{"content": "hello", "sender_id": "u1"}], True),
        ({"regex": "^u1 "}, {"sender_id": "u1 ", "x": 1}, True),
    ],
)
def test_operators(raw: Any, value: Any, expected: bool) -> None:
    assert holds(raw, value) is expected


@pytest.mark.parametrize(
    ("raw", "message"),
    [
        ({"contains": "x", "title": "y"}, "mixes operators"),
        ({"regex": "("}, "not a valid regular expression"),
        ({"min": "three"}, "needs a number"),
        ({"after": "soon"}, "'after'"),
        ({"contains_any": "x"}, "needs a list"),
        ({"one_of": "x"}, "needs a list"),
        ({"any_of": []}, "non-empty list"),
        ({"present": "yes"}, "true or false"),
        ({}, "empty mapping"),
    ],
)
def test_bad_matchers_are_refused(raw: Any, message: str) -> None:
    with pytest.raises(MatcherError, match=message):
        compile_matcher(raw)


def test_describe_reads_like_the_file() -> None:
    text = compile_matcher({"contains": ["a", "b"], "not": {"one_of": [1]}}).describe()
    assert "contains" in text and "not (" in text


def test_relative_times_resolve_against_each_start_however_often_they_are_read() -> None:
    """Parsed times are remembered by text and start: another start gives another time."""
    matcher = compile_matcher({"after": "day+1 09:00"})
    later = datetime(2025, 3, 10, 9, 0, tzinfo=UTC)
    for _ in range(2):
        assert matcher.test("2025-03-04T10:00:00Z", START)
        assert not matcher.test("2025-03-04T10:00:00Z", later)
    equal = compile_matcher("day+1 10:00")
    assert equal.test("2025-03-04T10:00:00Z", START) and not equal.test("2025-03-04T10:00:00Z", later)


def test_a_matcher_compiles_to_the_same_verdicts_as_written() -> None:
    """Operators made into functions keep their meaning: None is refused except by present and not."""
    assert not holds({"contains": "none"}, None) and holds({"not": {"contains": "x"}}, None)
    assert holds({"present": False}, None) and not holds({"present": True}, None)
    assert holds({"contains": ["ann", "bob"]}, [["Ann"], [{"to": "bob"}]])
    assert not holds({"contains": ["ann", "bob"]}, [])
    assert holds({"contains": "x", "not": {"contains": "y"}}, "x only")
    assert not holds({"contains": "x", "not": {"contains": "y"}}, "x and y")
    assert holds({"one_of": ["day+1 10:00", 3]}, "3") and holds(
        {"one_of": ["day+1 10:00"]}, "2025-03-04 10:00"
    )


def _frozen_by_isinstance(raw: Any) -> Any:
    """The matcher cache's key as first written (isinstance only), to hold the faster one to."""
    if isinstance(raw, Mapping):
        items = tuple((str(key), _frozen_by_isinstance(value)) for key, value in raw.items())
        return None if any(value is None for _, value in items) else ("map", items)
    if isinstance(raw, list | tuple):
        parts = tuple(_frozen_by_isinstance(item) for item in raw)
        return None if any(part is None for part in parts) else ("list", parts)
    if raw is None or isinstance(raw, str | int | float | bool | datetime | date | time):
        return (type(raw).__name__, raw)
    return None


class _Text(str):
    pass


_LEAVES = st.one_of(
    st.none(),
    st.booleans(),
    st.integers(),
    st.floats(allow_nan=False),
    st.text(max_size=4),
    st.dates(),
    st.datetimes(),
    st.times(),
    st.builds(_Text, st.text(max_size=3)),
    st.builds(object),
    st.builds(bytes),
)
_VALUES = st.recursive(
    _LEAVES,
    lambda inner: st.one_of(
        st.lists(inner, max_size=3),
        st.lists(inner, max_size=3).map(tuple),
        st.dictionaries(st.one_of(st.text(max_size=3), st.integers()), inner, max_size=3),
        st.dictionaries(st.text(max_size=3), inner, max_size=3).map(MappingProxyType),
    ),
    max_leaves=12,
)


@settings(max_examples=400, deadline=None)
@given(_VALUES)
def test_the_cache_key_of_a_matcher_is_the_one_isinstance_gives(raw: Any) -> None:
    assert _frozen(raw) == _frozen_by_isinstance(raw)
    assert type(_frozen(raw)) is type(_frozen_by_isinstance(raw))
