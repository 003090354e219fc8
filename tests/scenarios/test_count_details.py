"""Counts and parts of the day read by the judge fallback's facts rule."""

from __future__ import annotations

from collections.abc import Sequence
from datetime import UTC, datetime

import pytest

from pare.scenarios.fact_details import AllowedDetails, details

START = datetime(2025, 3, 3, 9, 0, tzinfo=UTC)  # a Monday morning


def _stray(facts: Sequence[str], text: str, sent: datetime = START) -> str | None:
    found = AllowedDetails.of(facts, START, lambda: ()).stray(text, sent)
    return None if found is None else found[0].shown


SHOES = ["Tom's shoe size is 11.", "The shop is on the 3rd floor.", "The flat has two bedrooms."]


@pytest.mark.parametrize(
    "text", ["He takes a size eleven", "size 11 please", "third floor", "floor 3", "a 2-bed", "2 bedrooms"]
)
def test_a_count_the_facts_give_is_allowed_in_words_or_digits(text: str) -> None:
    assert _stray(SHOES, text) is None


@pytest.mark.parametrize(
    ("text", "shown"),
    [
        ("Tom's size is twelve", "size is twelve"),
        ("It's on the fourth floor", "fourth floor"),
        ("a lovely one-bedroom flat", "one-bedroom"),
        ("the second-floor one", "second-floor"),
    ],
)
def test_a_count_the_facts_do_not_give_fails(text: str, shown: str) -> None:
    assert _stray(SHOES, text) == shown


def test_only_what_the_facts_count_is_checked() -> None:
    # the facts count no tickets and no minutes: those counts are the text's own business
    assert _stray(SHOES, "Got 2 tickets, see you in 10 minutes") is None


def test_lengths_of_time_are_one_family() -> None:
    facts = ["Priya moved to Rotterdam for two years."]
    assert _stray(facts, "for the two-year posting") is None
    assert _stray(facts, "at the hub for two months") == "two months"
    # an ordinal of a length of time is a place in time, not a length
    assert _stray(facts, "Hope the first weeks in Rotterdam go well") is None
    assert _stray(facts, "Good luck on the second day") is None


def test_a_range_allows_either_end_and_gives_both() -> None:
    facts = ["Simmer the soup for 20-25 minutes."]
    assert _stray(facts, "simmer for twenty to twenty-five minutes") is None
    assert _stray(facts, "simmer for 25 minutes") is None
    assert _stray(facts, "simmer for 40 minutes") == "40 minutes"


def test_an_ordinal_count_is_no_date() -> None:
    kinds = {detail.kind for detail in details("the 4th floor", START)}
    assert kinds == {"count"}


def test_a_hyphenated_compound_is_no_count() -> None:
    assert details("month-to-month studios", START) == ()


TRIP = ["The museum trip is on Sunday at 10:00."]


@pytest.mark.parametrize("text", ["Sunday morning at 10", "the Sunday trip, first thing"])
def test_a_part_of_day_holding_a_time_of_the_facts_is_allowed(text: str) -> None:
    assert _stray(TRIP, text) is None


def test_a_part_of_day_no_time_of_the_facts_falls_in_fails() -> None:
    assert _stray(TRIP, "It's on Sunday afternoon") == "afternoon"


def test_this_morning_is_allowed_when_sent_in_the_morning() -> None:
    assert _stray(TRIP, "I read your email this morning, Sunday works") is None
    evening = START.replace(hour=19)
    assert _stray(TRIP, "I read your email this afternoon, Sunday works", evening) == "this afternoon"


@pytest.mark.parametrize(
    ("text", "stray"),
    [
        ("The total is eighty-six pounds forty", None),
        ("The total is ninety-six pounds forty", "ninety-six pounds forty"),
        ("That's forty-eight dollars and forty-nine cents", "forty-eight dollars and forty-nine cents"),
    ],
)
def test_amounts_in_words_are_amounts(text: str, stray: str | None) -> None:
    assert _stray(["The claim totals £86.40."], text) == stray


def test_a_month_alone_is_read_where_the_facts_name_one() -> None:
    at = datetime(2025, 6, 10, 9, 0, tzinfo=UTC)
    facts = ["The raise has applied since April 2025."]
    found = AllowedDetails.of(facts, at, lambda: ())
    assert found.stray("It has applied since April", at) is None
    assert found.stray("since April this year", at) is None
    stray = found.stray("It has applied since April last year", at)
    assert stray is not None and stray[0].shown == "April last year"
    # "May I" is no month, and facts with days only leave months alone
    assert found.stray("May I ask about it?", at) is None
    assert AllowedDetails.of(["Paid on 1 April 2025."], at, lambda: ()).stray("the May payslip", at) is None


def test_an_amount_said_as_a_difference_may_be_what_two_given_amounts_differ_by() -> None:
    facts = ["The tent was $179 and is now $139."]
    assert _stray(facts, "Now $139, that's $40 less") is None
    assert _stray(facts, "Now $139: it saves you $40") is None
    assert _stray(facts, "Now $139, $30 less") == "$30"
    assert _stray(facts, "You owe $40") == "$40"  # not said as a difference
    assert _stray(["A budget of $80; the cups cost $36."], "Spent $36, $44 left") is None


def test_any_word_the_facts_count_is_a_label() -> None:
    facts = ["The deck must be 10 slides."]
    assert _stray(facts, "Ten slides, as asked") is None
    assert _stray(facts, "I made 12 slides") == "12 slides"
    # a number of three digits names a model, it counts nothing; function words are no labels
    assert _stray(["Order 2 cartridges."], "the 305 cartridge, 2 cartridges, 3 of them") is None
