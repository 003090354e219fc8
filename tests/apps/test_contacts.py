from __future__ import annotations

import pytest

from pare.env import Environment
from tests.conftest import err, make_env, ok, screen_of

SEED = {
    "contacts": {
        "contacts": {
            "me": {
                "contact_id": "me",
                "first_name": "Sam",
                "last_name": "Rivera",
                "is_user": True,
                "email": "sam@rivera.example",
            },
            "c-alice": {
                "contact_id": "c-alice",
                "first_name": "Alice",
                "last_name": "Chen",
                "email": "alice.chen@work.example",
                "phone": "+1 555 0101",
                "company": "Acme",
            },
            "c-bob": {
                "contact_id": "c-bob",
                "first_name": "Bob",
                "last_name": "Okafor",
                "phone": "+1 555 0102",
                "relationship": "landlord",
            },
            "c-carol": {
                "contact_id": "c-carol",
                "first_name": "Carol",
                "last_name": "Chen",
                "relationship": "sister",
            },
        }
    }
}


@pytest.fixture
def env() -> Environment:
    env = make_env(["contacts"], SEED)
    ok(env.call("user", "open_app", {"app_name": "contacts"}))
    return env


def contacts(env: Environment) -> dict:
    return env.snapshot()["contacts"]["contacts"]


def test_opens_on_the_list(env: Environment) -> None:
    assert screen_of(env) == "List"


def test_list_contacts_pages_sorted_by_name(env: Environment) -> None:
    page = ok(env.call("user", "list_contacts", {"limit": 2}))
    assert [c["first_name"] for c in page["contacts"]] == ["Alice", "Bob"]
    assert page["total"] == 4
    page = ok(env.call("user", "list_contacts", {"offset": 2, "limit": 5}))
    assert [c["first_name"] for c in page["contacts"]] == ["Carol", "Sam"]
    assert screen_of(env) == "List"


def test_search_contacts_matches_every_word(env: Environment) -> None:
    found = ok(env.call("user", "search_contacts", {"query": "chen"}))
    assert {c["contact_id"] for c in found} == {"c-alice", "c-carol"}
    found = ok(env.call("user", "search_contacts", {"query": "CHEN acme"}))
    assert [c["contact_id"] for c in found] == ["c-alice"]
    assert ok(env.call("user", "search_contacts", {"query": "landlord"}))[0]["contact_id"] == "c-bob"
    assert screen_of(env) == "List"


def test_view_current_user(env: Environment) -> None:
    assert ok(env.call("user", "view_current_user"))["contact_id"] == "me"
    assert screen_of(env) == "List"


def test_open_contact_goes_to_detail(env: Environment) -> None:
    shown = ok(env.call("user", "open_contact", {"contact_id": "c-bob"}))
    assert shown["first_name"] == "Bob"
    assert screen_of(env) == "Detail"
    assert ok(env.call("user", "view_contact"))["contact_id"] == "c-bob"


def test_open_unknown_contact_is_an_error_and_stays(env: Environment) -> None:
    err(env.call("user", "open_contact", {"contact_id": "nobody"}), "no contact with id 'nobody'")
    assert screen_of(env) == "List"


def test_create_contact_opens_the_new_contact(env: Environment) -> None:
    before = len(contacts(env))
    created = ok(env.call("user", "create_contact", {"first_name": "Dana", "phone": "+1 555 0199"}))
    assert screen_of(env) == "Detail"
    assert len(contacts(env)) == before + 1
    assert contacts(env)[created["contact_id"]]["phone"] == "+1 555 0199"
    assert env.log[-1].kind == "write"


def test_edit_flow_updates_and_returns_to_detail(env: Environment) -> None:
    ok(env.call("user", "open_contact", {"contact_id": "c-alice"}))
    ok(env.call("user", "start_edit_contact"))
    assert screen_of(env) == "Edit"
    assert ok(env.call("user", "view_contact"))["contact_id"] == "c-alice"
    ok(env.call("user", "update_contact", {"updates": {"phone": "+1 555 0000", "job": "CTO"}}))
    assert screen_of(env) == "Detail"
    assert contacts(env)["c-alice"]["phone"] == "+1 555 0000"
    assert contacts(env)["c-alice"]["job"] == "CTO"
    assert contacts(env)["c-alice"]["email"] == "alice.chen@work.example"


def test_update_with_unknown_field_is_rejected(env: Environment) -> None:
    ok(env.call("user", "open_contact", {"contact_id": "c-alice"}))
    ok(env.call("user", "start_edit_contact"))
    before = env.snapshot()
    err(env.call("user", "update_contact", {"updates": {"shoe_size": 9}}), "updates.shoe_size")
    assert env.snapshot() == before
    assert screen_of(env) == "Edit"


def test_delete_contact_returns_to_list(env: Environment) -> None:
    ok(env.call("user", "open_contact", {"contact_id": "c-bob"}))
    ok(env.call("user", "delete_contact"))
    assert screen_of(env) == "List"
    assert "c-bob" not in contacts(env)
    assert env.system.stacks["contacts"][-1].screen_name() == "List"
    assert len(env.system.stacks["contacts"]) == 1


def test_owner_card_cannot_be_deleted(env: Environment) -> None:
    ok(env.call("user", "open_contact", {"contact_id": "me"}))
    before = env.snapshot()
    err(env.call("user", "delete_contact"), "cannot be deleted")
    assert env.snapshot() == before
    assert screen_of(env) == "Detail"


def test_agent_api(env: Environment) -> None:
    def call(tool: str, **args: object) -> object:
        return ok(env.call("assistant", f"contacts__{tool}", args, mode="execute"))

    assert call("get_contacts", limit=1)["total"] == 4
    assert call("get_contact", contact_id="c-bob")["last_name"] == "Okafor"
    assert [c["contact_id"] for c in call("search_contacts", query="alice")] == ["c-alice"]
    assert call("get_current_user_details")["contact_id"] == "me"
    new_id = call("add_new_contact", first_name="Eve", email="eve@x.example", relationship="colleague")["id"]
    assert contacts(env)[new_id]["email"] == "eve@x.example"
    assert call("edit_contact", contact_id=new_id, updates={"last_name": "Moreau"})["last_name"] == "Moreau"
    call("delete_contact", contact_id=new_id)
    assert new_id not in contacts(env)


@pytest.mark.parametrize(
    ("tool", "args", "message"),
    [
        ("get_contact", {"contact_id": "ghost"}, "no contact with id 'ghost'"),
        ("get_contacts", {"limit": 0}, "limit"),
        ("search_contacts", {"query": "  "}, "empty"),
        ("add_new_contact", {"first_name": " "}, "first name"),
        ("edit_contact", {"contact_id": "c-bob", "updates": {}}, "no field"),
        ("edit_contact", {"contact_id": "c-bob", "updates": {"first_name": ""}}, "cannot be empty"),
        ("delete_contact", {"contact_id": "ghost"}, "ghost"),
    ],
)
def test_agent_api_errors_change_nothing(env: Environment, tool: str, args: dict, message: str) -> None:
    before = env.snapshot()
    err(env.call("assistant", f"contacts__{tool}", args, mode="execute"), message)
    assert env.snapshot() == before


def test_adding_a_contact_says_who_was_added(env: Environment) -> None:
    added = ok(
        env.call(
            "assistant",
            "contacts__add_new_contact",
            {"first_name": "Eve", "last_name": "Moreau"},
            mode="execute",
        )
    )
    assert added["done"] == f"Added Eve Moreau to the contacts as {added['id']}."
    assert contacts(env)[added["id"]]["last_name"] == "Moreau"
