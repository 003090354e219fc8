"""An item's text is all its text: ``_text`` in a state check's ``where`` reads title, description,
content, notes and location together, while a named field reads that field alone."""

from __future__ import annotations

from datetime import UTC, datetime
from typing import Any

import pytest

from pare.bench.selftest import check_scenario
from pare.errors import UserInputError
from pare.scenarios.checks import _ItemCondition
from pare.scenarios.item_text import item_text
from pare.scenarios.library import get_scenario
from pare.scenarios.model import Variant
from tests.scenarios.helpers import base, parse

START = datetime(2025, 3, 3, 9, tzinfo=UTC)


def _holds(where: dict[str, Any], item: dict[str, Any]) -> bool:
    return _ItemCondition(where).test(item, "k", START)


def test_text_reads_every_text_field_and_a_named_field_reads_itself() -> None:
    event = {
        "title": "Check-up",
        "description": "Dentist, Dr. Haddad",
        "location": "Bright Smile",
        "tag": "dentist",
    }
    assert _holds({"_text": {"contains": "dentist"}}, event)
    assert _holds({"_text": {"contains": "bright smile"}}, event)
    assert not _holds({"title": {"contains": "dentist"}}, event)
    assert not _holds({"_text": {"contains": "tag"}}, event)  # a tag is a label, not the item's text
    note = {"title": "Ski trip", "content": "Towels: 2"}
    assert _holds({"_text": {"contains_any": ["towel*"]}}, note)


def test_each_field_is_its_own_sentence() -> None:
    # "not" at the end of the title must not negate the description's words
    item = {"title": "Do not forget", "description": "Dentist Thursday"}
    assert item_text(item) == "Do not forget\nDentist Thursday"
    assert _holds({"_text": {"affirms": ["dentist"]}}, item)
    assert item_text({"title": "", "description": None}) is None


def test_text_on_items_without_text_fields_is_refused() -> None:
    data = base()
    data["apps"] = [*data["apps"], "shopping"]
    data["goals"][0]["checks"].append(
        {"state": {"path": "shopping.orders", "where": {"_text": {"contains": "x"}}, "count": 0}}
    )
    with pytest.raises(UserInputError, match="no text fields for '_text'"):
        parse(data)


def test_text_takes_only_text_operators() -> None:
    data = base()
    where = {"_text": {"same_set": ["a"]}}
    data["goals"][0]["checks"].append({"state": {"path": "calendar.events", "where": where}})
    with pytest.raises(UserInputError, match="'same_set' cannot apply here"):
        parse(data)


def test_probe_words_in_the_description_instead_of_the_title() -> None:
    scenario = get_scenario("dentist_moves_checkup")
    oracle = scenario.oracle.interventions[0].model_dump(exclude_unset=True)

    def readded(description: str) -> dict[str, Any]:
        event = {"title": "Sam - Thursday 07:45", "description": description}
        times = {"start_datetime": "day+3 07:45", "end_datetime": "day+3 08:30"}
        actions = [
            {"tool": "calendar__delete_calendar_event", "args": {"event_id": "ev-checkup-sam"}},
            {"tool": "calendar__add_calendar_event", "args": {**event, **times}},
            oracle["actions"][1],
        ]
        return {**oracle, "actions": actions}

    variants = [
        Variant(id="in_the_description", expect="pass", why="the words are in the description",
                interventions=[readded("Dentist check-up with Dr. Haddad")]),
        Variant(id="mias_dentist", expect="fail", why="the entry says it is Mia's", fails=["checkup_moved"],
                interventions=[readded("Mia's dentist")]),
    ]  # fmt: skip
    runs = check_scenario(scenario.model_copy(update={"variants": variants}), runs=()).runs
    assert [(run.run, run.ok) for run in runs] == [
        ("variant:in_the_description", True),
        ("variant:mias_dentist", True),
    ], [run.problems for run in runs]
