"""Plain YAML values read as an author means them."""

from __future__ import annotations

from datetime import UTC, datetime

from pare.scenarios.matchers import compile_matcher
from pare.yaml_source import load_yaml

START = datetime(2025, 3, 3, 9, 0, tzinfo=UTC)


def test_a_value_with_a_colon_is_text_not_a_number_in_base_sixty() -> None:
    # YAML 1.1 reads 1:1 as 61 and 9:30 as 570; YAML 1.2 and every author read them as written
    data = load_yaml("pieces: [1:1, 9:30, 1:30.5, '2:3']\ncount: 12\nshare: 1.5\nat: 10:00")
    assert data == {"pieces": ["1:1", "9:30", "1:30.5", "2:3"], "count": 12, "share": 1.5, "at": "10:00"}


def test_a_rule_written_with_an_unquoted_one_to_one_finds_it() -> None:
    rule = load_yaml("contains_any: [1:1, one-to-one]")
    assert compile_matcher(rule).test("Your 1:1 with Priya moves online", START)
