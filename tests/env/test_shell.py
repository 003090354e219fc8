from __future__ import annotations

import pytest

from pare.env import Environment
from tests.conftest import err, make_env, ok, screen_of
from tests.fixture_app import NotebookApp


@pytest.fixture
def env() -> Environment:
    return make_env([NotebookApp(), "contacts"])


def names(env: Environment) -> list[str]:
    return [tool.name for tool in env.user_tools()]


def test_home_screen_offers_open_app_but_not_go_home_or_back(env: Environment) -> None:
    assert env.system.foreground is None
    assert {"open_app", "get_current_time", "wait"} <= set(names(env))
    assert not {"go_home", "go_back", "switch_app", "accept_proposal"} & set(names(env))
    err(env.call("user", "go_home"), "not available here")
    err(env.call("user", "go_back"), "not available here")


def test_open_app_only_from_home(env: Environment) -> None:
    ok(env.call("user", "open_app", {"app_name": "notebook"}))
    assert env.system.foreground == "notebook"
    assert screen_of(env) == "Index"
    assert "open_app" not in names(env)
    err(env.call("user", "open_app", {"app_name": "contacts"}), "not available here")
    assert env.system.foreground == "notebook"


def test_open_unknown_app_suggests(env: Environment) -> None:
    error = err(env.call("user", "open_app", {"app_name": "contact"}), "no app called 'contact'")
    assert "Did you mean 'contacts'" in error
    assert env.system.foreground is None


def test_go_home_puts_app_in_background_and_open_app_resumes_it(env: Environment) -> None:
    env.app("notebook").load({"items": {"a": "x"}})
    ok(env.call("user", "open_app", {"app_name": "notebook"}))
    ok(env.call("user", "open_item", {"item_id": "a"}))
    ok(env.call("user", "go_home"))
    assert env.system.foreground is None
    assert env.system.background == ["notebook"]
    ok(env.call("user", "open_app", {"app_name": "notebook"}))
    assert screen_of(env) == "Page"
    assert env.system.background == []


def test_switch_app_between_background_apps_keeps_screens(env: Environment) -> None:
    env.app("notebook").load({"items": {"a": "x"}})
    ok(env.call("user", "open_app", {"app_name": "notebook"}))
    ok(env.call("user", "open_item", {"item_id": "a"}))
    ok(env.call("user", "go_home"))
    ok(env.call("user", "open_app", {"app_name": "contacts"}))
    assert "switch_app" in names(env)
    ok(env.call("user", "switch_app", {"app_name": "notebook"}))
    assert env.system.foreground == "notebook"
    assert screen_of(env) == "Page"
    assert env.system.background == ["contacts"]
    err(env.call("user", "switch_app", {"app_name": "notebook"}), "already the app on screen")
    err(env.call("user", "switch_app", {"app_name": "home"}), "go_home")
    ok(env.call("user", "switch_app", {"app_name": "contacts"}))
    assert screen_of(env) == "List"


def test_switch_app_to_app_never_opened_is_refused(env: Environment) -> None:
    ok(env.call("user", "open_app", {"app_name": "notebook"}))
    ok(env.call("user", "go_home"))
    err(env.call("user", "switch_app", {"app_name": "contacts"}), "not open in the background")


def test_switch_app_from_home(env: Environment) -> None:
    ok(env.call("user", "open_app", {"app_name": "notebook"}))
    ok(env.call("user", "go_home"))
    ok(env.call("user", "switch_app", {"app_name": "notebook"}))
    assert env.system.foreground == "notebook"


def test_go_back_only_with_a_previous_screen(env: Environment) -> None:
    env.app("notebook").load({"items": {"a": "x"}})
    ok(env.call("user", "open_app", {"app_name": "notebook"}))
    assert "go_back" not in names(env)
    ok(env.call("user", "open_item", {"item_id": "a"}))
    assert "go_back" in names(env)
    ok(env.call("user", "go_back"))
    assert screen_of(env) == "Index"
    err(env.call("user", "go_back"), "not available here")


def test_screen_actions_only_on_their_screen(env: Environment) -> None:
    ok(env.call("user", "open_app", {"app_name": "notebook"}))
    error = err(env.call("user", "type_text", {"text": "hi"}), "not available on this screen")
    assert "notebook > Page" in error
    assert "Available now:" in error


def test_failing_action_restores_its_screen_draft(env: Environment) -> None:
    env.app("notebook").load({"items": {"a": "x"}})
    ok(env.call("user", "open_app", {"app_name": "notebook"}))
    ok(env.call("user", "open_item", {"item_id": "a"}))
    ok(env.call("user", "type_text", {"text": "hello"}))
    err(env.call("user", "type_text", {"text": " world!"}), "no shouting")
    screen = env.system.current_screen()
    assert screen is not None and screen.model_dump()["draft"] == "hello"


def test_write_action_logged_once_as_the_users(env: Environment) -> None:
    env.app("notebook").load({"items": {"a": "x"}})
    ok(env.call("user", "open_app", {"app_name": "notebook"}))
    ok(env.call("user", "open_item", {"item_id": "a"}))
    before = len(env.log)
    ok(env.call("user", "save_copy"))
    assert len(env.log) == before + 1
    entry = env.log[-1]
    assert (entry.actor, entry.app, entry.tool, entry.kind) == ("user", "notebook", "save_copy", "write")
    assert entry.screen == "notebook > Page(item_id='a', draft='')"
    assert screen_of(env) == "Index"


def test_undeclared_transition_is_a_bug_not_silence(env: Environment) -> None:
    from pare.errors import SimulationBug

    ok(env.call("user", "open_app", {"app_name": "notebook"}))
    with pytest.raises(SimulationBug, match="declares leads_to"):
        env.call("user", "broken_jump")


def test_get_current_time_for_both_actors(env: Environment) -> None:
    assert ok(env.call("user", "get_current_time")) == "2025-03-03T09:00:00+00:00"
    assert ok(env.call("assistant", "system__get_current_time")) == "2025-03-03T09:00:00+00:00"


def test_the_user_s_tools_follow_a_screen_class_given_new_actions(
    env: Environment, monkeypatch: pytest.MonkeyPatch
) -> None:
    # the named tools are made once per class; a class whose table is replaced is named again
    ok(env.call("user", "open_app", {"app_name": "notebook"}))
    screen = type(env.system.current_screen())
    first, *rest = screen.actions
    assert names(env)[: len(screen.actions)] == [first, *rest]
    monkeypatch.setattr(screen, "actions", {name: screen.actions[name] for name in rest})
    assert names(env)[: len(rest)] == rest
    assert first not in names(env)
