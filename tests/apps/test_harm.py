"""Harm classes: every write tool of every registered app says how bad a wrong call is, no other tool
does, and a declaration that names a wrong tool or class is refused when the app is defined."""

from __future__ import annotations

from typing import Any

import pytest
from pydantic import BaseModel, Field

from pare.apps.base import App
from pare.apps.harm import HARMS, unclassified_writes
from pare.apps.registry import app_names, get_app_class
from pare.apps.tools import tool
from pare.errors import SimulationBug
from tests.conftest import make_env

EVERY_APP = app_names(include_core=True)


@pytest.mark.parametrize("name", EVERY_APP)
def test_every_write_tool_is_classified(name: str) -> None:
    cls = get_app_class(name)
    assert unclassified_writes(cls) == [], f"{name}: classify these in {cls.__name__}.harm"
    for spec in cls.tools.values():
        if spec.kind == "write":
            assert spec.harm in HARMS, spec.name
            assert spec.harm == cls.harm[spec.name]


@pytest.mark.parametrize("name", EVERY_APP)
def test_no_read_or_world_tool_is_classified(name: str) -> None:
    cls = get_app_class(name)
    assert all(spec.harm is None for spec in cls.tools.values() if spec.kind != "write")
    assert set(cls.harm) <= {spec.name for spec in cls.tools.values() if spec.kind == "write"}


def test_the_classes_follow_what_undoing_a_wrong_call_takes() -> None:
    def harm(app: str, name: str) -> str | None:
        return get_app_class(app).tools[name].harm

    assert harm("calendar", "add_calendar_event") == "reversible"
    assert harm("notes", "update_note") == "reversible"
    assert harm("shopping", "checkout") == "costly"
    assert harm("cab", "user_cancel_ride") == "costly"
    assert harm("email", "send_email") == "irreversible"
    assert harm("messaging", "send_message") == "irreversible"
    assert harm("files", "delete") == "irreversible"


def test_the_assistants_flat_tools_carry_their_class() -> None:
    env = make_env(["email", "calendar"])
    execute = {named.name: named.spec for named in env.assistant_tools("execute")}
    assert execute["email__send_email"].harm == "irreversible"
    assert execute["calendar__add_calendar_event"].harm == "reversible"
    assert execute["email__search_emails"].harm is None


class _State(BaseModel):
    items: dict[str, str] = Field(default_factory=dict)


def _define(declared: dict[str, Any]) -> type[App]:
    class Jotter(App):
        name = "jotter"
        title = "Jotter"
        State = _State
        harm = declared

        @tool("read")
        def list_items(self) -> dict[str, str]:
            """List every item.

            Returns:
                item ids and texts.
            """
            return {}

        @tool("write")
        def add_item(self, text: str) -> str:
            """Add an item.

            Args:
                text: the item's text.
            """
            return text

    return Jotter


def test_a_declaration_is_put_on_the_tools() -> None:
    app = _define({"add_item": "costly"})
    assert app.tools["add_item"].harm == "costly"
    assert app.tools["list_items"].harm is None


@pytest.mark.parametrize(
    ("harm", "named"),
    [
        ({"add_items": "reversible"}, "'add_items', which is not a tool of the app"),
        ({"list_items": "reversible"}, "'list_items', a read tool"),
        ({"add_item": "undoable"}, "harm['add_item'] is 'undoable'"),
    ],
)
def test_a_wrong_declaration_is_refused_naming_the_tool(harm: dict[str, Any], named: str) -> None:
    with pytest.raises(SimulationBug, match=r"Jotter\.harm") as caught:
        _define(harm)
    assert named in str(caught.value)


def test_a_subclass_with_a_new_write_is_reported_unclassified() -> None:
    parent = _define({"add_item": "reversible"})

    class Extended(parent):  # type: ignore[valid-type, misc]
        name = "jotter_plus"

        @tool("write")
        def wipe(self) -> str:
            """Delete every item.

            Returns:
                what was deleted.
            """
            return ""

    assert Extended.tools["add_item"].harm == "reversible"
    assert unclassified_writes(Extended) == ["wipe"]
