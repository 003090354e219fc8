"""Codes and streets read by the judge fallback's facts rule."""

from __future__ import annotations

from collections.abc import Sequence
from datetime import UTC, datetime

import pytest

from pare.scenarios.fact_details import AllowedDetails, details

START = datetime(2025, 3, 3, 9, 0, tzinfo=UTC)


def _stray(facts: Sequence[str], text: str) -> str | None:
    found = AllowedDetails.of(facts, START, lambda: ()).stray(text, START)
    return None if found is None else found[0].shown


ORDER = ["Order HX-20931 is delivered to Flat 4B, 12 Pell Street, LS1 4AB; part no. 12008453."]


@pytest.mark.parametrize(
    "text",
    [
        "Your order hx 20931 comes to flat 4B",
        "Delivery to 12 Pell Street, LS1 4AB",
        "Pell Street, postcode LS14AB, part 12008453",
    ],
)
def test_a_code_or_street_the_facts_give_is_allowed_however_written(text: str) -> None:
    assert _stray(ORDER, text) is None


@pytest.mark.parametrize(
    ("text", "shown"),
    [
        ("Your order HX-20391 is on its way", "HX-20391"),
        ("Delivered to flat 4A", "4A"),
        ("Delivered to 21 Pell Street", "21 Pell Street"),
        ("Delivered to Abbot Street", "Abbot Street"),
        ("part no. 12008435", "no. 12008435"),
    ],
)
def test_a_code_or_street_the_facts_do_not_give_fails(text: str, shown: str) -> None:
    assert _stray(ORDER, text) == shown


def test_times_units_and_counts_are_no_codes() -> None:
    kinds = {detail.kind for detail in details("at 7pm, a 2-bed, 18h15, 5km, the 4th, Q3", START)}
    assert "code" not in kinds


def test_a_word_before_a_street_name_is_no_part_of_it() -> None:
    assert _stray(["The flat is on Willow Row."], "Saved Willow Row for you") is None


def test_facts_without_codes_or_streets_leave_them_alone() -> None:
    assert _stray(["Lunch is at 12:30."], "Order HX-1 to 3 Elm Road at 12:30") is None


def test_a_number_given_for_a_street_wins_over_a_mention_without_one() -> None:
    facts = ["The flat is at 22 Cedar Road.", "Oliver holds Cedar Road until Thursday."]
    assert _stray(facts, "Cedar Road is held for you") is None
    assert _stray(facts, "22 Cedar Road is held for you") is None
    assert _stray(facts, "9 Cedar Road is held for you") == "9 Cedar Road"
    assert _stray(["The bill is for 7 Birch Street."], "the bill for 3 Kiln Yard") == "3 Kiln Yard"
