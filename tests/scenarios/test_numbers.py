"""A number in text is its digits: found whatever its grouping, its country code or its leading 0."""

from __future__ import annotations

import pytest

from pare.scenarios.matchers import MatcherError, compile_matcher
from pare.scenarios.numbers import names_number


@pytest.mark.parametrize(
    "text",
    [
        "her mobile is 07700 900742",
        "mobile 0770 090 0742, thanks",
        "07700-900-742",
        "call +44 7700 900742",
        "0044 (0)7700 900742",
        "+447700900742",
    ],
)
def test_a_uk_number_is_found_in_any_grouping(text: str) -> None:
    assert names_number(text, "07700 900742")
    assert names_number(text, "+44 7700 900742")


@pytest.mark.parametrize(
    "text",
    [
        "07700 9007421",  # a longer number
        "107700 900742",
        "07700 900417",  # another number
        "7700 900 74",
    ],
)
def test_another_or_a_longer_number_is_not_the_number(text: str) -> None:
    assert not names_number(text, "07700 900742")


def test_a_number_with_a_country_code_is_found_in_its_national_forms() -> None:
    for text in ["(415) 555-0178", "415.555.0178", "+1 415 555 0178", "+14155550178"]:
        assert names_number(text, "+1 (415) 555-0178"), text
    assert not names_number("555-0178", "+1 (415) 555-0178")  # the area code is part of the number


def test_the_operator_reads_text_and_refuses_what_is_no_number() -> None:
    rule = compile_matcher({"mentions_number": "+34 612 555 081"})
    assert rule.test("Mobile: 612 55 50 81", None)  # type: ignore[arg-type]
    assert not rule.test("Mobile: 612 55 50 18", None)  # type: ignore[arg-type]
    with pytest.raises(MatcherError, match="mentions_number"):
        compile_matcher({"mentions_number": "no digits"})
    with pytest.raises(MatcherError, match="mentions_number"):
        compile_matcher({"mentions_number": ["07700 900742"]})
