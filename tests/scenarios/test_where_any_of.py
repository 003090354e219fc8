"""A state check's ``where`` can accept an item on one field or another (``any_of``)."""

from __future__ import annotations

from collections.abc import Mapping
from datetime import UTC, datetime
from types import MappingProxyType
from typing import Any

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from pare.bench import run_episode
from pare.errors import UserInputError
from pare.scenarios import OracleAssistant, OracleUser
from pare.scenarios.checks import _ItemCondition, _record
from pare.scenarios.model import WHERE_KEY
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


def _holds_as_written(condition: _ItemCondition, item: Any, key: str) -> bool:
    """A ``where`` as first written (every field's matcher on the item read as a mapping), to hold the
    compiled one to."""
    record = item if isinstance(item, Mapping) else {}
    fields = all(
        matcher.test(key if name == WHERE_KEY else record.get(name), START)
        for name, matcher in condition.fields
    )
    alternatives = condition.alternatives
    return fields and (
        not alternatives or any(_holds_as_written(option, item, key) for option in alternatives)
    )


START = datetime(2025, 3, 3, 9, 0, tzinfo=UTC)
_WHERES = [
    {},
    {"title": "Standup"},
    {"title": {"contains": "stand*"}, "n": {"min": 2}},
    {"_key": {"regex": "^ev"}, "start": {"after": "day+1 00:00"}},
    {"any_of": [{"title": "Standup"}, {"_key": "ev1"}]},
    {"n": {"max": 3}, "any_of": [{"title": {"contains": "lunch"}}, {"start": {"present": False}}]},
]
_FIELD_VALUES = st.one_of(
    st.none(),
    st.integers(0, 5),
    st.sampled_from(["Standup", "standup meeting", "Lunch", "2025-03-04T10:00:00Z", "2025-03-02 10:00"]),
)
_ITEMS = st.one_of(
    st.dictionaries(st.sampled_from(["title", "n", "start"]), _FIELD_VALUES, max_size=3),
    st.dictionaries(st.sampled_from(["title", "n"]), _FIELD_VALUES, max_size=2).map(MappingProxyType),
    _FIELD_VALUES,
    st.lists(_FIELD_VALUES, max_size=2),
)


@settings(max_examples=600, deadline=None)
@given(st.sampled_from(_WHERES), _ITEMS, st.sampled_from(["ev1", "ev-2", "x"]))
def test_a_where_holds_where_its_fields_and_one_alternative_do(
    where: dict[str, Any], item: Any, key: str
) -> None:
    """The compiled condition (each item read as a record once, fields in cheapest order) decides as
    its fields and alternatives read one by one do."""
    condition = _ItemCondition(where)
    assert condition.test(_record(item), key, START) is _holds_as_written(condition, item, key)
