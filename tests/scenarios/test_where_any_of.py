"""A state check's ``where`` can accept an item on one field or another (``any_of``)."""

from __future__ import annotations

from typing import Any

import pytest

from pare.bench import run_episode
from pare.errors import UserInputError
from pare.scenarios import OracleAssistant, OracleUser
from tests.scenarios.helpers import base, parse


def _with_goal(where: dict[str, Any]) -> dict[str, Any]:
    data = base()
    data["goals"].append(
        {
            "id": "standup_kept",
            "description": "The standup is still there, by its title or its description.",
            "checks": [{"state": {"path": "calendar.events", "where": where, "count": 1}}],
        }
    )
    return data


def _verdict(where: dict[str, Any]) -> bool:
    scenario = parse(_with_goal(where))
    return run_episode(scenario, OracleUser(scenario), OracleAssistant(scenario)).success


def test_one_alternative_is_enough_and_plain_fields_still_all_hold() -> None:
    either = {"any_of": [{"description": {"contains": "standup"}}, {"title": {"contains": "standup"}}]}
    assert _verdict(either)
    assert not _verdict(
        {"any_of": [{"description": {"contains": "standup"}}, {"title": {"contains": "lunch"}}]}
    )
    assert not _verdict({**either, "tag": "work"})  # the other fields must hold as well


def test_a_wrong_field_inside_any_of_is_named_where_it_is() -> None:
    with pytest.raises(UserInputError, match=r"where.any_of\[1\].titel: .*no field 'titel'"):
        parse(_with_goal({"any_of": [{"title": {"contains": "a"}}, {"titel": {"contains": "b"}}]}))
    with pytest.raises(UserInputError, match="lists alternatives"):
        parse(_with_goal({"any_of": {"title": "Standup"}}))


def test_a_keyed_collection_is_filtered_by_its_key() -> None:
    assert _verdict({"_key": {"equals": "ev1"}, "title": "Standup"})
    assert not _verdict({"_key": {"regex": "^ev-"}})
