"""Bad calls come back as clear error results, are logged, and change nothing."""

from __future__ import annotations

from typing import Any

import pytest

from pare.env import Environment
from tests.conftest import err, make_env, ok
from tests.fixture_app import NotebookApp


@pytest.fixture
def env() -> Environment:
    env = make_env([NotebookApp(), "contacts"])
    env.app("notebook").load({"items": {"a": "x"}})
    return env


CASES: list[tuple[str, str, Any, str | None, tuple[str, ...]]] = [
    ("assistant", "notebook__nope", {}, "execute", ("unknown tool 'notebook__nope'",)),
    ("assistant", "notebook_list_items", {}, "observe", ("did you mean 'notebook__list_items'",)),
    ("assistant", "notebook__add_item", {"text": "x"}, "observe", ("only in execute mode",)),
    ("assistant", "notebook__arrive", {"text": "x"}, "execute", ("not available to the assistant",)),
    ("assistant", "agent_ui__accept_proposal", {}, "observe", ("not available to the assistant",)),
    ("assistant", "notebook__add_item", {}, "execute", ("missing required argument 'text'",)),
    (
        "assistant",
        "notebook__add_item",
        {"text": "x", "colour": "red"},
        "execute",
        ("unexpected argument 'colour'",),
    ),
    (
        "assistant",
        "notebook__add_item",
        {"text": "x", "count": "many"},
        "execute",
        ("argument 'count'", "valid integer", "add_item(text: str, count: int = 1)"),
    ),
    ("assistant", "notebook__add_item", {"text": ["x"]}, "execute", ("argument 'text'",)),
    ("assistant", "notebook__add_item", ["x"], "execute", ("must be a json object",)),
    ("assistant", "notebook__add_item", {"text": ""}, "execute", ("needs text",)),
    ("user", "add_item", {"text": "x"}, None, ("unknown action 'add_item'", "available now: open_app")),
    ("user", "open_item", {"item_id": "a"}, None, ("not available on this screen", "notebook > Index")),
    ("user", "open_app", {}, None, ("missing required argument 'app_name'",)),
    ("user", "open_app", {"app_name": "notebook", "fast": True}, None, ("unexpected argument 'fast'",)),
    ("user", "open_app", {"app_name": 3}, None, ("argument 'app_name'",)),
    ("env", "contacts__get_contact", {"contact_id": "nobody"}, None, ("no contact with id 'nobody'",)),
]


@pytest.mark.parametrize(("actor", "tool", "args", "mode", "fragments"), CASES)
def test_bad_call_is_an_error_result_logged_without_state_change(
    env: Environment, actor: str, tool: str, args: Any, mode: str | None, fragments: tuple[str, ...]
) -> None:
    before = env.snapshot(include_navigation=True)
    count = len(env.log)
    result = env.call(actor, tool, args, mode=mode)  # type: ignore[arg-type]
    err(result, *fragments)
    assert env.snapshot(include_navigation=True) == before
    assert len(env.log) == count + 1
    entry = env.log[-1]
    assert not entry.ok and entry.error == result.error and entry.actor == actor


def test_backend_errors_on_screens_leave_user_where_they_were(env: Environment) -> None:
    ok(env.call("user", "open_app", {"app_name": "notebook"}))
    before = env.snapshot(include_navigation=True)
    err(env.call("user", "open_item", {"item_id": "zzz"}), "no item zzz")
    assert env.snapshot(include_navigation=True) == before


def test_internal_errors_are_returned_when_not_in_strict_mode() -> None:
    from pare.env import EnvConfig

    env = Environment([NotebookApp()], EnvConfig())
    env.app("notebook").state = None  # type: ignore[assignment]  # break the app on purpose
    result = env.call("assistant", "notebook__list_items", {}, mode="observe")
    err(result, "internal error in notebook.list_items", "bug in pare")
    assert env.log[-1].ok is False


MISUSE: list[tuple[Any, Any, Any, tuple[str, ...]]] = [
    ("hacker", "notebook__add_item", None, ("unknown actor 'hacker'", "user, assistant, env, oracle")),
    (None, "notebook__list_items", None, ("unknown actor none",)),
    ("user", 123, None, ("tool name must be a non-empty string", "123")),
    ("assistant", None, None, ("tool name must be a non-empty string",)),
    ("assistant", "", None, ("tool name must be a non-empty string",)),
    ("assistant", "notebook__add_item", "banana", ("unknown assistant mode 'banana'", "observe, execute")),
    ("user", "open_app", "execute", ("only the assistant calls tools in a mode",)),
]


@pytest.mark.parametrize(("actor", "tool", "mode", "fragments"), MISUSE)
def test_python_misuse_of_call_is_refused_not_raised_and_grants_nothing(
    env: Environment, actor: Any, tool: Any, mode: Any, fragments: tuple[str, ...]
) -> None:
    """A caller's mistake (not an actor, not a tool name, not a mode) is an error result: no exception,
    no log entry (the log holds only the four actors' calls), no access, no change."""
    before = env.snapshot(include_navigation=True)
    result = env.call(actor, tool, {"text": "sneaked in"}, mode=mode)
    err(result, *fragments)
    assert result.entry is None
    assert len(env.log) == 0
    assert env.snapshot(include_navigation=True) == before
