from __future__ import annotations

from collections import UserDict
from collections.abc import Mapping
from datetime import UTC, datetime, timedelta
from datetime import date as Date

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from pare.scenarios.times import (
    _DAY,
    _OFFSET,
    TimeFormatError,
    is_relative_time,
    parse_duration,
    parse_time,
    resolve_relative_times,
)

START = datetime(2025, 3, 3, 9, 0, tzinfo=UTC)


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        ("+15m", START + timedelta(minutes=15)),
        ("-2h", START - timedelta(hours=2)),
        ("+1d2h30m", START + timedelta(days=1, hours=2, minutes=30)),
        ("+45s", START + timedelta(seconds=45)),
        ("day+1 09:30", datetime(2025, 3, 4, 9, 30, tzinfo=UTC)),
        ("day-2 18:00", datetime(2025, 3, 1, 18, 0, tzinfo=UTC)),
        ("day 14:00", datetime(2025, 3, 3, 14, 0, tzinfo=UTC)),
        ("day+1 7:05:30", datetime(2025, 3, 4, 7, 5, 30, tzinfo=UTC)),
        ("2025-03-05T10:00:00Z", datetime(2025, 3, 5, 10, 0, tzinfo=UTC)),
        ("2025-03-05 10:00", datetime(2025, 3, 5, 10, 0, tzinfo=UTC)),
        ("2025-03-05T10:00:00+01:00", datetime(2025, 3, 5, 9, 0, tzinfo=UTC)),
    ],
)
def test_time_forms(text: str, expected: datetime) -> None:
    assert parse_time(text, START) == expected


@pytest.mark.parametrize("text", ["tomorrow", "+15", "day+1", "day+1 25:00", "+1x", "15m"])
def test_bad_times_say_which_forms_work(text: str) -> None:
    with pytest.raises(TimeFormatError):
        parse_time(text, START)


def test_bad_time_message_lists_the_forms() -> None:
    with pytest.raises(TimeFormatError, match=r"\+15m.*day\+1 09:00"):
        parse_time("next tuesday", START)


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        ("10m", timedelta(minutes=10)),
        ("1h30m", timedelta(minutes=90)),
        ("2d", timedelta(days=2)),
        ("0", timedelta(0)),
        (90, timedelta(seconds=90)),
    ],
)
def test_durations(text: str | int, expected: timedelta) -> None:
    assert parse_duration(text) == expected


@pytest.mark.parametrize("text", ["ten minutes", "-5m", "5", -3])
def test_bad_durations(text: str | int) -> None:
    with pytest.raises(TimeFormatError):
        parse_duration(text)


def test_only_whole_relative_strings_are_resolved() -> None:
    data = {
        "timestamp": "-2h",
        "nested": [{"due": "day+1 08:00"}],
        "content": "see you at +15m past",
        "subject": "+15m",  # a whole string in relative form is a time, by design
        "count": 3,
    }
    resolved = resolve_relative_times(data, START)
    assert resolved["timestamp"] == "2025-03-03T07:00:00+00:00"
    assert resolved["nested"][0]["due"] == "2025-03-04T08:00:00+00:00"
    assert resolved["content"] == "see you at +15m past"
    assert resolved["count"] == 3
    assert is_relative_time(" +15m ") and not is_relative_time("15m")


def test_dates_and_times_yaml_read_as_such_become_iso_text() -> None:
    """An unquoted timestamp in a tool's arguments must not reach the log as a datetime (the trajectory
    would not be JSON)."""
    import json

    from pare.scenarios.times import resolve_relative_times

    start = datetime(2025, 3, 3, 9, 0, tzinfo=UTC)
    resolved = resolve_relative_times(
        {
            "due": datetime(2026, 4, 23, 9, 0),
            "day": Date(2026, 4, 23),
            "at": [datetime(2026, 4, 23, 9, 0, tzinfo=UTC)],
        },
        start,
    )
    assert resolved == {
        "due": "2026-04-23T09:00:00+00:00",
        "day": "2026-04-23",
        "at": ["2026-04-23T09:00:00+00:00"],
    }
    json.dumps(resolved)


def _relative_by_patterns(text: str) -> bool:
    """is_relative_time as first written (the two patterns alone), to hold the quicker one to."""
    stripped = text.strip()
    return bool(_OFFSET.match(stripped.replace(" ", "")) or _DAY.match(stripped))


@settings(max_examples=600, deadline=None)
@given(
    st.one_of(
        st.text(alphabet=st.sampled_from(list("+-dayDA 0123456789:hms\t\n\u2003\u00a0x")), max_size=14),
        st.text(max_size=8),
        st.builds(
            "{}{}{}".format,
            st.sampled_from(["", " ", "\t", "\u2003", "x"]),
            st.sampled_from(["+15m", "-2h", "+1d2h", "day+1 09:00", "day 14:00", "day - 2 18:30", "Day 1"]),
            st.sampled_from(["", " ", "\n", "z"]),
        ),
    )
)
def test_is_relative_time_gives_what_the_patterns_give(text: str) -> None:
    assert is_relative_time(text) is _relative_by_patterns(text)


def _resolved_by_the_type_chain(data: object, start: datetime) -> object:
    """resolve_relative_times as first written (every value through the chain of isinstance checks)."""
    if isinstance(data, str):
        return parse_time(data, start).isoformat() if _relative_by_patterns(data) else data
    if isinstance(data, datetime):
        return (data if data.tzinfo else data.replace(tzinfo=UTC)).isoformat()
    if isinstance(data, Date):
        return data.isoformat()
    if isinstance(data, Mapping):
        return {key: _resolved_by_the_type_chain(value, start) for key, value in data.items()}
    if isinstance(data, list):
        return [_resolved_by_the_type_chain(value, start) for value in data]
    return data


class _Text(str):
    pass


class _Table(UserDict[str, object]):
    pass


_SEED_LEAVES = st.one_of(
    st.none(),
    st.booleans(),
    st.integers(),
    st.floats(allow_nan=False),
    st.sampled_from(["+15m", " -2h", "day+1 09:30", "\tday 14:00", "dinner", "", " ", "d", "+", "x-1"]),
    st.text(max_size=6),
    st.builds(_Text, st.sampled_from(["+1h", "lunch"])),
    st.datetimes(timezones=st.sampled_from([UTC, None])),
    st.dates(),
    st.tuples(st.integers()),
)


@settings(max_examples=300, deadline=None)
@given(
    st.recursive(
        _SEED_LEAVES,
        lambda children: st.one_of(
            st.lists(children, max_size=4),
            st.dictionaries(st.text(max_size=3), children, max_size=4),
            st.builds(_Table, st.dictionaries(st.text(max_size=3), children, max_size=3)),
        ),
        max_leaves=20,
    )
)
def test_resolving_seed_data_gives_what_the_type_chain_gives(data: object) -> None:
    assert resolve_relative_times(data, START) == _resolved_by_the_type_chain(data, START)
