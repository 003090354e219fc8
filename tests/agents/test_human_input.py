"""What a person types in the user's seat becomes one valid action on the screen, or a message that
says what was wrong (never an action the screen does not offer)."""

from __future__ import annotations

import pytest

from pare.agents.human_input import (
    HumanInputError,
    SeatLeft,
    ToolChoice,
    action_from_fields,
    argument_fields,
    argument_value,
    find_tool,
    menu,
    read_typed_action,
)
from pare.agents.policy import Action
from pare.env import EnvConfig, UserView
from pare.scenarios.build import build_environment
from pare.scenarios.library import get_scenario


def _views() -> tuple[UserView, UserView]:
    """The home screen, and an open email's screen of the same phone."""
    env = build_environment(get_scenario("dentist_moves_checkup"), EnvConfig())
    home = env.user_view()
    env.call("user", "open_app", {"app_name": "email"})
    env.call("user", "open_email", {"email_id": "email-710"})
    return home, env.user_view()


HOME, EMAIL = _views()


def test_a_menu_number_without_arguments_is_the_action_itself() -> None:
    number = menu(HOME).index(find_tool(HOME, "wait")) + 1
    assert read_typed_action(str(number), HOME) == Action("wait")


def test_a_menu_number_with_arguments_asks_for_them_in_signature_order() -> None:
    number = menu(EMAIL).index(find_tool(EMAIL, "reply")) + 1
    chosen = read_typed_action(f" {number} ", EMAIL)
    assert isinstance(chosen, ToolChoice)
    assert [(f.name, f.required, f.text) for f in chosen.fields] == [
        ("content", True, True),
        ("attachments", False, False),
    ]
    assert chosen.fields[1].type_text == "list[str] | None"


def test_a_name_with_json_arguments_the_action_format_and_bare_json_give_the_same_action() -> None:
    wanted = Action("open_app", {"app_name": "email"})
    typed = [
        'open_app {"app_name": "email"}',
        'Action: {"action": "open_app", "action_input": {"app_name": "email"}}',
        '{"action": "open_app", "action_input": {"app_name": "email"}}',
    ]
    for line in typed:
        action = read_typed_action(line, HOME)
        assert isinstance(action, Action)
        assert (action.tool, action.args) == (wanted.tool, wanted.args)


@pytest.mark.parametrize(
    ("typed", "says"),
    [
        ("", "number from the menu"),
        ("99", "no action 99"),
        ("0", "choose 1 to"),
        ("open_mail", "Did you mean 'open_app'"),
        ("reply {}", "missing required argument 'content'"),
        ('open_app {"app": "email"}', "unexpected argument 'app'"),
        ("open_app {app_name: email}", "must be one JSON object"),
        ('open_app ["email"]', "must be a JSON object"),
        ("Action: {'action': 'wait'}", "single quotes"),
        ('{"action": "send_email"}', "'send_email' is not an action on this screen"),
    ],
)
def test_what_cannot_be_an_action_here_is_refused_with_the_reason(typed: str, says: str) -> None:
    view = EMAIL if typed.startswith("reply") else HOME
    with pytest.raises(HumanInputError) as refused:
        read_typed_action(typed, view)
    assert says in str(refused.value)


def test_quit_leaves_the_seat() -> None:
    with pytest.raises(SeatLeft):
        read_typed_action("  QUIT ", HOME)


def test_argument_values_text_as_typed_lists_as_json_and_defaults_when_left_empty() -> None:
    reply = find_tool(EMAIL, "reply")
    content, attachments = argument_fields(reply)
    assert argument_value(content, " Thursday, 07:45 ") == (True, " Thursday, 07:45 ")
    assert argument_value(attachments, "") == (False, None)
    assert argument_value(attachments, '["a.pdf"]') == (True, ["a.pdf"])
    with pytest.raises(HumanInputError, match="'content' is required"):
        argument_value(content, "")
    with pytest.raises(HumanInputError, match="must be written as JSON"):
        argument_value(attachments, "[a.pdf")


def test_a_form_of_typed_fields_gives_the_action_and_refuses_unknown_fields_and_wrong_types() -> None:
    action = action_from_fields(EMAIL, "reply", {"content": "Thursday works", "attachments": ""})
    assert (action.tool, action.args) == ("reply", {"content": "Thursday works"})
    with pytest.raises(HumanInputError, match="no argument 'contents'"):
        action_from_fields(EMAIL, "reply", {"contents": "x"})
    with pytest.raises(HumanInputError, match="argument 'offset'"):
        env = build_environment(get_scenario("dentist_moves_checkup"), EnvConfig())
        env.call("user", "open_app", {"app_name": "email"})
        action_from_fields(env.user_view(), "list_emails", {"offset": "three"})
    with pytest.raises(HumanInputError, match="not an action on this screen"):
        action_from_fields(HOME, "reply", {"content": "x"})
