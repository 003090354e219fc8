"""What the user sees on arriving at a screen, and when the screen's data changes under their eyes."""

from __future__ import annotations

import json

from pare.apps.registry import app_names
from pare.apps.sample_data import START, sample_world
from pare.env import Environment
from tests.conftest import make_env, ok


def _env() -> Environment:
    return make_env(app_names(), sample_world(), start_time=START)


def test_opening_an_app_shows_its_first_screen_without_a_list_call() -> None:
    env = _env()
    result = env.call("user", "open_app", {"app_name": "email"})
    assert result.ok and result.screen_display is not None
    observation = result.observation()
    assert observation.startswith("email > Mailbox")
    shown = json.loads(observation.split("On screen: ", 1)[1])
    assert "email-" in json.dumps(shown)  # the ids the user needs to open an email
    assert result.entry is not None and result.entry.result == result.value  # the log keeps the call's result


def test_switching_back_and_going_back_show_the_screen_arrived_on() -> None:
    env = _env()
    ok(env.call("user", "open_app", {"app_name": "messaging"}))
    ok(env.call("user", "open_conversation", {"conversation_id": "conv-family"}))
    back = env.call("user", "go_back")
    assert back.ok and "On screen: " in back.observation() and "conv-family" in back.observation()
    ok(env.call("user", "go_home"))
    ok(env.call("user", "open_app", {"app_name": "calendar"}))
    ok(env.call("user", "go_home"))
    switched = env.call("user", "open_app", {"app_name": "messaging"})
    assert "On screen: " in switched.observation()


def test_an_action_that_shows_its_item_is_not_followed_by_a_second_copy() -> None:
    env = _env()
    ok(env.call("user", "open_app", {"app_name": "messaging"}))
    opened = env.call("user", "open_conversation", {"conversation_id": "conv-family"})
    assert opened.ok and opened.screen_display is None


def test_a_message_arriving_in_the_open_conversation_appears_on_screen_in_full() -> None:
    env = _env()
    ok(env.call("user", "open_app", {"app_name": "messaging"}))
    ok(env.call("user", "open_conversation", {"conversation_id": "conv-family"}))
    assert env.user_view().screen_update is None  # nothing changed since the user looked
    long = "Dinner is at eight at the new place on Harbour Street, bring the board game and a warm jacket"
    ok(
        env.call(
            "env",
            "messaging__receive_message",
            {"sender": "Carol", "content": long, "conversation_id": "conv-family"},
        )
    )
    view = env.user_view()
    assert view.screen_update is not None and long in json.dumps(view.screen_update, ensure_ascii=False)
    assert long in view.render()  # in full on the screen, whatever the notification cut
    assert env.user_view().screen_update is None  # shown once


def test_a_change_in_another_app_does_not_redraw_the_screen_on_view() -> None:
    env = _env()
    ok(env.call("user", "open_app", {"app_name": "messaging"}))
    ok(
        env.call(
            "env",
            "email__receive_email",
            {"sender": "a@x.example", "subject": "Hi", "content": "Hello"},
        )
    )
    assert env.user_view().screen_update is None
