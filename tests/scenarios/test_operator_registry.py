"""Matcher operators are records in one registry: the schema, the guide's table and matching read it."""

from __future__ import annotations

import json
from collections.abc import Iterator
from datetime import UTC, datetime
from typing import Any

import pytest

from pare.bench import run_episode
from pare.scenarios import OracleAssistant, OracleUser
from pare.scenarios.explain import explain
from pare.scenarios.kinds import matcher_problems
from pare.scenarios.matchers import (
    OPERATORS,
    MatcherError,
    Operator,
    compile_matcher,
    register_operator,
    unregister_operator,
)
from pare.scenarios.operator_docs import operator_table
from pare.scenarios.schema import scenario_json_schema
from pare.scenarios.stats import _reads_text
from tests.scenarios.helpers import base, parse

START = datetime(2025, 3, 3, 9, 0, tzinfo=UTC)


def _suffix(value: Any) -> str:
    if not isinstance(value, str) or not value:
        raise MatcherError(f"'ends_with' needs a non-empty string, got {value!r}")
    return value.casefold()


def _ends_with(suffix: str, value: Any, start: datetime) -> bool:
    return isinstance(value, str) and value.casefold().rstrip(" .!?").endswith(suffix)


def _why_not(text: str, suffix: str, start: datetime) -> str:
    return f"it ends with {text.split()[-1]!r}"


ENDS_WITH = Operator(
    "ends_with",
    "a string",
    "is text whose last words are the string, case-insensitively (final punctuation aside)",
    _ends_with,
    _suffix,
    reads="text",
    explain=_why_not,
)


@pytest.fixture
def ends_with() -> Iterator[Operator]:
    register_operator(ENDS_WITH)
    try:
        yield ENDS_WITH
    finally:
        unregister_operator(ENDS_WITH.name)


def _matcher_descriptions() -> list[str]:
    found: list[str] = []

    def walk(node: Any) -> None:
        if isinstance(node, dict):
            text = node.get("description")
            if isinstance(text, str) and text.startswith("A value (equal to it), a mapping of operators"):
                found.append(text)
            for value in node.values():
                walk(value)
        elif isinstance(node, list):
            for value in node:
                walk(value)

    walk(scenario_json_schema())
    return found


def test_a_registered_operator_is_in_the_schema_the_guides_table_and_matching(ends_with: Operator) -> None:
    descriptions = _matcher_descriptions()
    assert descriptions and all(f"ends_with (a string): {ends_with.doc}" in text for text in descriptions)
    assert f"| `ends_with` | a string | {ends_with.doc} |" in operator_table().splitlines()

    matcher = compile_matcher({"ends_with": "See you then", "contains": "thursday"})
    assert matcher.test("Thursday works. See you then!", START)
    assert not matcher.test("See you then. Thursday works", START)
    assert not matcher.test(None, START)  # refuses a missing value, as operators do by default
    assert matcher.describe() == "ends_with 'see you then' and contains ['thursday']"
    assert matcher.cost == 2
    assert explain(matcher, "Thursday works", START) == "ends_with 'see you then': it ends with 'works'"
    with pytest.raises(MatcherError, match="'ends_with' needs a non-empty string"):
        compile_matcher({"ends_with": 3})

    # a text operator: it cannot apply to a number, and a check with it reads free text
    assert [message for _, message in matcher_problems({"ends_with": "x"}, int)] == [
        "'ends_with' cannot apply here: this field holds a number"
    ]
    assert not list(matcher_problems({"ends_with": "x"}, str))
    assert _reads_text({"not": {"ends_with": "x"}})


def test_a_registered_operator_works_in_a_scenario_file(ends_with: Operator) -> None:
    data = base()
    content = data["goals"][0]["checks"][0]["action"]["args"]["content"]
    content["ends_with"] = "works"  # the oracle replies "Thursday works!"
    scenario = parse(data)
    result = run_episode(scenario, OracleUser(scenario), OracleAssistant(scenario))
    assert result.success, result.outcome.failures()
    content["ends_with"] = "does not work"
    scenario = parse(data)
    result = run_episode(scenario, OracleUser(scenario), OracleAssistant(scenario))
    (failure,) = result.outcome.failures()
    assert "ends_with 'does not work'" in failure.detail
    data["goals"][0]["checks"][0]["action"]["args"]["email_id"] = {"ends_with": "ann"}
    parse(data)  # an id is text: the operator applies


def test_an_unregistered_operator_is_gone_everywhere() -> None:
    register_operator(ENDS_WITH)
    assert compile_matcher({"ends_with": "x"}).operators == (("ends_with", "x"),)
    unregister_operator("ends_with")
    assert "ends_with" not in OPERATORS
    assert not any("ends_with" in text for text in _matcher_descriptions())
    assert "ends_with" not in operator_table()
    # a mapping with that key reads as a record's field again (the compiled matcher is not kept)
    assert compile_matcher({"ends_with": "x"}).fields


def test_a_taken_or_unusable_name_is_refused() -> None:
    with pytest.raises(ValueError, match="'contains' is already registered"):
        register_operator(OPERATORS["contains"])
    with pytest.raises(ValueError, match="is a word"):
        register_operator(Operator("_text", "a string", "is it", _ends_with))


def test_every_operator_is_documented_and_described_once() -> None:
    schema = json.dumps(scenario_json_schema())
    for operator in OPERATORS.values():
        assert operator.takes and operator.doc and not operator.doc.endswith(".")
        assert f"{operator.name} ({operator.takes}): " in schema
    assert len(operator_table().splitlines()) == len(OPERATORS) + 2
