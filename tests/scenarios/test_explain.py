"""A failing matcher says which part failed on which clause, and why."""

from __future__ import annotations

from datetime import UTC, datetime
from typing import Any

import pytest

from pare.scenarios.excerpts import excerpt, quote
from pare.scenarios.explain import explain
from pare.scenarios.matchers import compile_matcher

START = datetime(2025, 3, 3, 9, tzinfo=UTC)  # a Monday: day+3 is Thursday 6 March


def _why(raw: Any, value: Any) -> str:
    return explain(compile_matcher(raw), value, START)


def test_a_negated_mention_names_the_clause_and_the_cue() -> None:
    why = _why({"affirms": ["move*"]}, "not Fri and could we move it?")
    clause = 'clause "not Fri and could we move it"'
    assert why == f"affirms 'move*': found 'move' in {clause} but it is negated by 'not'"
    why = _why({"affirms": "move*"}, "I am not sure we should have moved it")
    assert (
        "found 'moved' in clause \"I am not sure we should have moved it\" but it is negated by 'not'" in why
    )


def test_a_long_clause_is_shortened_around_the_cue_and_the_word() -> None:
    text = "not Fri any chance we could perhaps find a way to move it to some other day this week"
    why = _why({"affirms": "move*"}, text)
    clause = why.split('clause "')[1].split('"')[0]
    assert clause.startswith("not Fri") and "move it" in clause and "…" in clause
    assert len(clause) < len(text)


def test_a_missing_word_says_where_it_hides_inside_another() -> None:
    assert _why({"contains": "wed"}, "I reviewed it") == (
        "contains 'wed': 'wed' is not in the text as a whole word (only inside 'reviewed')"
    )
    assert "'friday' is not in the text" in _why({"contains": ["wed", "friday"]}, "Wed it is")


def test_any_of_explains_every_alternative() -> None:
    why = _why({"any_of": [{"affirms": "thursday"}, {"mentions_day": "day+4"}]}, "Thursday does not work")
    assert why.startswith("any of: none holds (")
    assert "negated by 'not'" in why
    assert "mentions_day day+4 (Fri 7 Mar): the text names days or times only in negated clauses" in why
    assert "Thu 6 Mar in \"Thursday does not work\" negated by 'not'" in why


def test_days_and_times_named_elsewhere_are_listed() -> None:
    why = _why({"mentions_time": "day+3 08:00"}, "Thursday works. 6pm is best.")
    assert why.startswith("mentions_time day+3 08:00 (Thu 6 Mar 08:00): the text names")
    assert "Thu 6 Mar (sentence 1)" in why and "18:00 (sentence 2)" in why


@pytest.mark.parametrize(
    ("raw", "text", "said"),
    [
        ({"declines": True}, "Sure, see you then", "no clause refuses"),
        ({"declines": False}, "Sorry, I can't make it", 'reads as a refusal: clause "I can\'t make it"'),
        (
            {"declines": True},
            "I can't make Thursday, how about Friday?",
            "takes up another option ('how about'): a counter-offer",
        ),
    ],
)
def test_declines_says_which_clause_decided(raw: Any, text: str, said: str) -> None:
    assert said in _why(raw, text)


def test_values_that_are_not_text() -> None:
    assert _why({"min": 3}, 2) == "min 3.0: got 2"
    assert _why({"present": True}, None) == "the value is missing"
    assert _why({"contains": "x"}, None) == "contains ['x']: the value is missing"
    assert _why({"not": {"contains": "b"}}, "b") == "not (contains ['b']): it holds"
    assert _why({"start_datetime": "day+3 08:00"}, {"start_datetime": "2025-03-06T09:00:00Z"}).startswith(
        "start_datetime: equals 'day+3 08:00': got"
    )
    assert "none of its 2 items matches" in _why({"title": {"contains": "x"}}, [{"title": "y"}, {}])


def test_a_text_without_days_says_so() -> None:
    assert _why({"mentions_clock": "08:00"}, "see you soon") == "mentions_clock 08:00: the text names none"


def test_nothing_to_explain_when_the_matcher_holds() -> None:
    assert _why({"affirms": "thursday"}, "Thursday works") == ""


def test_quoted_text_is_one_line_shortened_in_the_middle() -> None:
    text = "Hello Ann,\n\n" + "a very long message " * 10 + "see you Thursday"
    shown = quote(text)
    assert shown.startswith('"Hello Ann, a very') and shown.endswith('see you Thursday"')
    assert "\n" not in shown and " … " in shown and len(shown) <= 84
    assert excerpt("short one") == "short one"
