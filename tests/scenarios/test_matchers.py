from __future__ import annotations

import pickle
from collections.abc import Mapping
from datetime import UTC, date, datetime, time
from types import MappingProxyType
from typing import Any

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from pare.scenarios.matchers import Matcher, MatcherError, _frozen, _operator_check, compile_matcher
from pare.scenarios.meaning import has_word, normalise_quotes
from pare.scenarios.operators import _contains, _contains_any, _leaves, _text, _time
from pare.scenarios.times import TimeFormatError, parse_time

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
        ({"before": "day+1 10:00"}, "2025-03-04T10:00:00Z", False),  # before excludes its bound
        ({"before": "day+1 10:00"}, "2025-03-04T09:59:00Z", True),
        ({"by": "day+1 10:00"}, "2025-03-04T10:00:00Z", True),  # by includes it
        ({"by": "day+1 10:00"}, "2025-03-04T10:01:00Z", False),
        ({"after": "day+1 10:00"}, "2025-03-04T10:00:00Z", False),  # after excludes its bound
        ({"after": "day+1 10:00"}, "2025-03-04T10:01:00Z", True),
        ({"from": "day+1 10:00"}, "2025-03-04T10:00:00Z", True),  # from includes it
        ({"from": "day+1 10:00"}, "2025-03-04T09:59:00Z", False),
        ({"from": "day+1 00:00", "before": "day+2 00:00"}, "2025-03-05T00:00:00Z", False),  # a whole day
        ({"from": "day+1 00:00", "before": "day+2 00:00"}, "2025-03-04T00:00:00Z", True),
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


def _test_as_written(matcher: Matcher, value: Any, start: datetime) -> bool:
    """A matcher's test as first written (one loop over its operators' checks), to hold the test made
    for each matcher's shape to."""
    if matcher.fields:
        if isinstance(value, list):
            return any(_test_as_written(matcher, item, start) for item in value)
        if not isinstance(value, Mapping):
            return False
        return all(_test_as_written(field, value.get(key), start) for key, field in matcher.fields)
    for name, expected in matcher.operators:
        check, prepared, needs_value = _operator_check(name, expected)
        if (needs_value and value is None) or not check(prepared, value, start):
            return False
    return True


def _time_as_written(value: Any, start: datetime) -> datetime | None:
    if isinstance(value, datetime):
        return value if value.tzinfo else value.replace(tzinfo=UTC)
    if not isinstance(value, str):
        return None
    try:
        return parse_time(value, start)
    except TimeFormatError:
        return None


_RAW_MATCHERS = [
    "email-1",
    3,
    True,
    None,
    "day+1 10:00",
    datetime(2025, 3, 4, 10, 0),
    ["a", "b"],
    {"equals": "a"},
    {"contains": "thursday"},
    {"contains": ["thu*", "8"]},
    {"contains": "it's"},
    {"contains_any": ["2pm", "14:00", "a b"]},
    {"affirms": "thursday"},
    {"declines": True},
    {"mentions_day": "day+3"},
    {"mentions_clock": "18:15"},
    {"mentions_time": "day+3 18:15"},
    {"regex": "^a"},
    {"one_of": ["a", 3, "day+1 10:00"]},
    {"same_set": ["A", "b"]},
    {"min": 2},
    {"max": 5.5},
    {"after": "day+1 00:00"},
    {"before": "day+1 23:59"},
    {"after": "day+1 00:00", "before": "day+1 23:59"},
    {"from": "day+1 00:00", "by": "day+1 23:59"},
    {"present": True},
    {"present": False},
    {"not": {"contains": "x"}},
    {"not": "a"},
    {"any_of": [{"contains": "a"}, {"min": 3}]},
    {"contains": "a", "not": {"contains": "b"}},
    {"title": {"contains": "a"}},
    {"title": "a", "n": {"min": 2}},
    {"item": {"title": "a"}},
]
_WORDS = st.sampled_from(
    ["a", "b", "A b", "thursday", "Thu 8", "it\u2019s", "2pm", "14:00", "x", "can't make it", "", "3", " b "]
)
_JSON = st.recursive(
    st.one_of(
        st.none(),
        st.booleans(),
        st.integers(-3, 8),
        st.floats(allow_nan=False),
        _WORDS,
        st.text(max_size=6),
        st.sampled_from(["2025-03-04T10:00:00Z", "2025-03-04 10:00", "day+1 10:00", "2025-03-04T12:00:00"]),
        st.datetimes(min_value=datetime(2025, 3, 1), max_value=datetime(2025, 3, 9)),
        st.builds(_Text, _WORDS),
    ),
    lambda inner: st.one_of(
        st.lists(inner, max_size=3),
        st.dictionaries(st.sampled_from(["title", "n", "item", "x"]), inner, max_size=3),
        st.dictionaries(st.sampled_from(["title", "n"]), inner, max_size=2).map(MappingProxyType),
    ),
    max_leaves=8,
)


@settings(max_examples=1500, deadline=None)
@given(st.sampled_from(_RAW_MATCHERS), _JSON)
def test_a_matchers_test_gives_the_verdict_of_its_operators_checks(raw: Any, value: Any) -> None:
    """The test made for a matcher's shape (fields, one operator, several) is the loop it replaces."""
    matcher = compile_matcher(raw)
    assert matcher.test(value, START) is _test_as_written(matcher, value, START)


@settings(max_examples=500, deadline=None)
@given(_JSON)
def test_times_and_texts_are_read_as_before(value: Any) -> None:
    """The exact-type shortcuts read what the isinstance chains read."""
    assert _time(value, START) == _time_as_written(value, START)
    if isinstance(value, str):
        assert normalise_quotes(value) == value.replace("\u2019", "'").replace("\u2018", "'")
    pieces = ("a", "thu*", "it's", "a b", "14:00")
    texts = [_text(item) for item in _leaves(value)]
    assert _contains(pieces[:2], value, START) is all(any(has_word(t, p) for t in texts) for p in pieces[:2])
    assert _contains_any(pieces, value, START) is any(has_word(t, p) for p in pieces for t in texts)


def test_a_compiled_matcher_survives_pickling() -> None:
    """Its test is a closure, made again when the matcher is unpickled."""
    matcher = compile_matcher({"title": {"contains": "a"}, "n": {"min": 2}})
    again = pickle.loads(pickle.dumps(matcher))
    assert again == matcher and again.test({"title": "a b", "n": 2}, START)
    assert not again.test({"title": "a b", "n": 1}, START)


START_MONDAY = datetime(2025, 3, 3, 9, 0, tzinfo=UTC)


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        ("See you at quarter past five", True),  # the reader's wordings, not the author's regex
        ("Pick-up at 5pm, or 17:15 if the bus is late", True),
        ("half five works", False),  # 17:30: the wrong time however it is written
        ("Pick up at 6pm", False),
        ("Not 6pm, 5.15 instead", True),  # a time in a negated clause is not stated
        ("No time named here", True),
        ("between 5 and 6", False),  # both ends of a range count
    ],
)
def test_only_clocks_allows_the_listed_times_in_any_wording(text: str, expected: bool) -> None:
    assert compile_matcher({"only_clocks": ["17:00", "17:15"]}).test(text, START_MONDAY) is expected


@pytest.mark.parametrize(
    ("text", "expected"),
    [("Thursday works", True), ("Thu 6 March then", True), ("Friday then", False), ("tomorrow", False)],
)
def test_only_days_reads_days_as_of_when_the_text_was_written(text: str, expected: bool) -> None:
    assert compile_matcher({"only_days": ["day+3"]}).test(text, START_MONDAY) is expected


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        ("It was £14.99 from the £120 kitty", True),
        ("It cost 26.99 pounds", False),
        ("not £26.99 but £14.99", True),
        ("$120 exactly", True),  # the value, whatever the sign: a story has one currency
        ("about £15 in the end", True),  # a rough amount near a listed one (2 %)
        ("£15 in the end", False),
        ("about £16 in the end", False),
    ],
)
def test_only_amounts_allows_the_listed_amounts(text: str, expected: bool) -> None:
    assert compile_matcher({"only_amounts": ["14.99", "£120"]}).test(text, START_MONDAY) is expected


@pytest.mark.parametrize(
    ("raw", "message"),
    [
        ({"only_clocks": []}, "needs a non-empty list"),
        ({"only_clocks": ["25:00"]}, "'mentions_clock' needs a clock time"),
        ({"only_amounts": ["lots"]}, "'only_amounts' needs amounts"),
        ({"only_days": "day+3"}, "needs a non-empty list"),
    ],
)
def test_only_matchers_refuse_what_they_cannot_read(raw: Any, message: str) -> None:
    with pytest.raises(MatcherError, match=message):
        compile_matcher(raw)


def test_only_clocks_explains_the_stray_time() -> None:
    from pare.scenarios import explain

    matcher = compile_matcher({"only_clocks": ["17:00"]})
    assert "names 18:00" in explain.explain(matcher, "Pick up at 6pm", START_MONDAY)


def test_in_a_clause_keeps_an_excuse_with_what_it_excuses() -> None:
    put_forward = {"in_a_clause": {"contains": "harbour", "not": {"contains_any": ["skipped", "left out"]}}}
    assert holds(put_forward, "Saved Willow Row, and Harbour Walk too")
    assert not holds(put_forward, "I saved Willow Row and skipped Harbour Walk")
    assert not holds(put_forward, "Harbour Walk I left out, Willow is saved")
    assert not holds(put_forward, "Willow Row is saved")


def test_in_a_sentence_wants_both_in_one_sentence() -> None:
    promised = {"in_a_sentence": {"affirms": ["bring*"], "mentions_day": "day+3"}}
    assert holds(promised, "I'll bring it Thursday. Friday I'm away.")
    assert not holds(promised, "I'll bring it. Thursday I'm away.")
    assert "in_a_sentence (affirms" in compile_matcher(promised).describe()


def test_only_clocks_takes_spans() -> None:
    window = compile_matcher({"only_clocks": ["14:00-18:00", "19:30"]})
    assert window.test("ready from 4.20pm, or at half seven", START_MONDAY)
    assert not window.test("come at 1pm", START_MONDAY)
    assert window.describe() == "only_clocks [14:00-18:00, 19:30]"
    with pytest.raises(MatcherError, match="ends before it starts"):
        compile_matcher({"only_clocks": ["18:00-14:00"]})


def test_negated_reads_a_clause_for_a_negation_cue() -> None:
    charged_again = {"in_a_clause": {"contains": "again", "negated": False}}
    assert holds(charged_again, "Not me, and they also charged me again")
    assert not holds(charged_again, "It was not charged again")
    assert holds({"negated": True}, "I can't make Thursday")
    assert not holds({"negated": True}, "No problem, Thursday works")


def test_not_lets_a_text_turn_down_what_it_bans() -> None:
    # a forbidden pattern does not fire on a clause that negates or passes over what it names
    assert holds({"not": {"regex": "oat drink"}}, "Got the barista one, not the regular oat drink")
    assert holds({"not": {"contains": "2kg"}}, "Ordered the 5kg bag rather than the 2kg bag")
    assert holds({"not": {"contains_any": ["change", "move"]}}, "7:45 works, no need to change it")
    assert not holds({"not": {"regex": "oat drink"}}, "Got the regular oat drink")
    # a match in a negated clause that covers the clause's own cue still counts: the pattern seeks it
    assert not holds({"not": {"regex": "can't make"}}, "Sorry, I can't make Friday")
    assert not holds({"not": {"contains": "not sure"}}, "I'm not sure about Friday")
    # a pattern spanning clauses is judged by the clause it begins in
    assert not holds({"not": {"regex": r"ordered[^.]*toaster"}}, "I ordered the cups, and the toaster too")
    assert holds({"not": {"regex": r"ordered[^.]*toaster"}}, "I haven't ordered yet, the toaster is gone")
    # a later match in a clause that affirms still counts
    assert not holds({"not": {"contains": "oat"}}, "Not the oat one. Actually, oat it is")
    # options of an any_of under not are read the same way
    assert holds({"not": {"any_of": [{"contains": "oat"}, {"equals": 3}]}}, "not the oat drink")
    assert not holds({"not": {"any_of": [{"contains": "oat"}, {"equals": 3}]}}, 3)


def test_not_inside_a_part_or_an_option_reads_its_words_anywhere() -> None:
    # in a clause already chosen, or as a whole any_of option, a not excuses: its words count anywhere
    claimed = {"in_a_clause": {"contains": "annecy", "not": {"contains_any": ["personal"]}}}
    assert not holds(claimed, "I'm not claiming the Annecy personal weekend")
    assert holds(claimed, "Annecy is on the claim")
    unmentioned = {"any_of": [{"not": {"contains": "porto"}}, {"equals": 1}]}
    assert not holds(unmentioned, "Skipped the box (Porto)")
    assert holds(unmentioned, "Skipped the box")
    # beside other operators in an option, a not bans as it does outside
    energy_not_bill = {"any_of": [{"contains": "energy", "not": {"contains": "bill"}}, {"equals": 1}]}
    assert holds(energy_not_bill, "Energy readings are in, not the estimated bill")
    assert not holds(energy_not_bill, "Energy bill is due")
