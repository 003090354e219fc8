"""Suggestions for a mistyped name: letter by letter, and word by word for names one word off."""

from __future__ import annotations

import pytest

from pare.errors import closest_names, did_you_mean
from pare.scenarios.validation import ToolCatalog

TOOLS = list(ToolCatalog(["messaging", "calendar", "email", "contacts", "reminder"]).flat)


@pytest.mark.parametrize(
    ("typed", "meant"),
    [
        ("agent_ui__send_message_to_users", "agent_ui__send_message_to_user"),  # a word inflected
        ("calendar__create_calendar_event", "calendar__add_calendar_event"),  # the verb tools use alike
        ("calendar__create_event", "calendar__add_calendar_event"),  # a word missing, the verb alike
        ("calendar__delete_event", "calendar__delete_calendar_event"),  # a word missing
        ("email__recieve_email", "email__receive_email"),  # a typo, as before
    ],
)
def test_the_name_meant_comes_first(typed: str, meant: str) -> None:
    assert closest_names(typed, TOOLS)[0] == meant


def test_a_name_one_word_off_is_found_among_names_that_share_more_letters() -> None:
    choices = ["send_message", "send_message_to_group_conversation", "read_messages", "send_message_to_user"]
    assert closest_names("send_message_to_users", choices)[0] == "send_message_to_user"
    assert closest_names("create_event", ["create_calendar_event", "delete_contact"]) == [
        "create_calendar_event"
    ]


def test_a_name_with_the_same_words_is_suggested_alone() -> None:
    assert (
        did_you_mean("calendar__create_calendar_event", TOOLS)
        == " Did you mean 'calendar__add_calendar_event'?"
    )


@pytest.mark.parametrize(
    ("typed", "choices"),
    [
        ("go_sideways", ["go_back", "go_home"]),  # one shared word is not a likeness
        ("set_colour", ["set_day", "set_tag", "set_title"]),
        ("archive_folder", ["delete_email", "move_email"]),
    ],
)
def test_no_suggestion_from_one_shared_word(typed: str, choices: list[str]) -> None:
    assert did_you_mean(typed, choices) == ""
