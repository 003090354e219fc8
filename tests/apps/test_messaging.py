from __future__ import annotations

from datetime import timedelta

import pytest

from pare.env import Environment
from pare.errors import UserInputError
from tests.conftest import err, make_env, ok, screen_of

USERS = {
    "u-sam": "Sam Rivera",
    "u-alice": "Alice Chen",
    "u-bob": "Bob Okafor",
    "u-carol": "Carol Chen",
    "u-dev": "Dev Patel",
    "u-emma": "Emma Larsen",
    "u-farid": "Farid Haddad",
    "u-grace": "Grace Kim",
    "u-hiro": "Hiro Tanaka",
    "u-ines": "Inès Moreau",
}


def msg(message_id: str, sender: str, when: str, content: str, attachment: str | None = None) -> dict:
    return {
        "message_id": message_id,
        "sender_id": sender,
        "timestamp": f"2025-{when}",
        "content": content,
        "attachment": attachment,
    }


SEED = {
    "files": {
        "files": {
            "/Documents/lease.pdf": {"content": "Lease agreement, 14 Elm St, from April 1."},
            "/Photos/summit.jpg": {"content": "JPEG summit photo"},
            "/Documents/agenda.txt": {"content": "1. Budget 2. Hiring"},
        }
    },
    "messaging": {
        "current_user_id": "u-sam",
        "users": USERS,
        "conversations": {
            "c-alice": {
                "conversation_id": "c-alice",
                "participant_ids": ["u-sam", "u-alice"],
                "messages": [
                    msg("m-a1", "u-alice", "03-01T09:15", "Hey! Did you get a chance to look at the flat?"),
                    msg("m-a2", "u-sam", "03-01T09:40", "Yes, I loved it. Can you send me the lease?"),
                    msg("m-a3", "u-alice", "03-02T10:00", "Here it is", "/Documents/lease.pdf"),
                ],
            },
            "c-bob": {
                "conversation_id": "c-bob",
                "participant_ids": ["u-sam", "u-bob"],
                "messages": [
                    msg("m-b1", "u-bob", "02-27T08:00", "Reminder: rent is due on the 1st."),
                    msg("m-b2", "u-sam", "02-27T08:30", "Thanks Bob, transfer scheduled."),
                ],
            },
            "c-dev": {
                "conversation_id": "c-dev",
                "participant_ids": ["u-sam", "u-dev"],
                "messages": [msg("m-d1", "u-dev", "03-02T18:00", "Are we still on for squash tomorrow?")],
            },
            "g-family": {
                "conversation_id": "g-family",
                "participant_ids": ["u-sam", "u-carol", "u-hiro"],
                "title": "Family",
                "messages": [
                    msg("m-f1", "u-carol", "03-02T19:00", "Mum's birthday dinner is on Saturday"),
                    msg("m-f2", "u-hiro", "03-02T20:00", "I'll book the Italian place"),
                ],
            },
            "g-hike": {
                "conversation_id": "g-hike",
                "participant_ids": ["u-sam", "u-grace", "u-farid", "u-ines"],
                "title": "Hiking crew",
                "messages": [
                    msg("m-h1", "u-grace", "02-28T17:00", "Trail next weekend?"),
                    msg("m-h2", "u-ines", "03-01T08:00", "Summit view!", "/Photos/summit.jpg"),
                ],
            },
            "g-work": {
                "conversation_id": "g-work",
                "participant_ids": ["u-sam", "u-alice", "u-dev"],
                "messages": [msg("m-w1", "u-dev", "02-25T12:00", "Lunch at noon?")],
            },
        },
    },
}
RECENT_ORDER = ["g-family", "c-dev", "c-alice", "g-hike", "c-bob", "g-work"]
LONG = (
    "Hi Sam, quick heads up about the plumber: he can only come on Thursday between two and four, "
    "so please leave the spare key with the concierge. The secret word is PINEAPPLE."
)


@pytest.fixture
def env() -> Environment:
    env = make_env(["messaging"], SEED)
    ok(env.call("user", "open_app", {"app_name": "messaging"}))
    return env


def state(env: Environment) -> dict:
    return env.snapshot()["messaging"]


def conversations(env: Environment) -> dict:
    return state(env)["conversations"]


def last_message(env: Environment, conversation_id: str) -> dict:
    return conversations(env)[conversation_id]["messages"][-1]


def call(env: Environment, tool: str, **args: object) -> object:
    return ok(env.call("assistant", f"messaging__{tool}", args, mode="execute"))


def receive(env: Environment, **args: object) -> dict:
    return ok(env.call("env", "messaging__receive_message", args))


# -- seed data ---------------------------------------------------------------------------------------


def test_seed_is_normalised() -> None:
    env = make_env(["messaging"], SEED)
    data = state(env)
    assert data["current_user_name"] == "Sam Rivera"
    assert data["conversations"]["g-hike"]["is_group"] is True
    assert data["conversations"]["c-alice"]["is_group"] is False
    assert data["conversations"]["c-alice"]["last_updated"].startswith("2025-03-02T10:00")


def test_default_state_has_the_current_user() -> None:
    env = make_env(["messaging"])
    assert state(env)["users"] == {"user-me": "Me"}


@pytest.mark.parametrize(
    ("conversation", "message"),
    [
        ({"conversation_id": "x", "participant_ids": ["u-sam", "u-nobody"]}, "not users"),
        ({"conversation_id": "x", "participant_ids": ["u-alice", "u-bob"]}, "current user"),
        ({"conversation_id": "y", "participant_ids": ["u-sam", "u-alice"]}, "different id"),
        ({"conversation_id": "x", "participant_ids": ["u-sam", "u-bob"]}, "both one-to-one"),
    ],
)
def test_bad_seed_is_refused(conversation: dict, message: str) -> None:
    seed = {
        "messaging": {
            "current_user_id": "u-sam",
            "users": USERS,
            "conversations": {**SEED["messaging"]["conversations"], "x": conversation},
        }
    }
    with pytest.raises(UserInputError, match=message):
        make_env(["messaging"], seed)


def test_seed_checks_the_current_user_and_senders() -> None:
    users = {"u-sam": "Sam Rivera", "u-bob": "Bob Okafor"}
    with pytest.raises(UserInputError, match="differs"):
        make_env(
            ["messaging"],
            {"messaging": {"current_user_id": "u-sam", "current_user_name": "Sam", "users": users}},
        )
    bad_sender = {
        "conversation_id": "c",
        "participant_ids": ["u-sam", "u-bob"],
        "messages": [msg("m1", "u-ghost", "03-01T09:00", "boo")],
    }
    with pytest.raises(UserInputError, match="unknown user"):
        make_env(
            ["messaging"],
            {"messaging": {"current_user_id": "u-sam", "users": users, "conversations": {"c": bad_sender}}},
        )
    env = make_env(["messaging"], {"messaging": {"current_user_id": "u-x", "current_user_name": "Xavi"}})
    assert state(env)["users"] == {"u-x": "Xavi"}


def test_get_user_id_with_two_people_of_one_name_is_an_error() -> None:
    users = {"u-sam": "Sam Rivera", "u-al1": "Alex Kim", "u-al2": "Alex Kim"}
    env = make_env(["messaging"], {"messaging": {"current_user_id": "u-sam", "users": users}})
    err(
        env.call("assistant", "messaging__get_user_id", {"user_name": "alex kim"}),
        "several",
        "u-al1",
        "u-al2",
    )


# -- List screen -------------------------------------------------------------------------------------


def test_opens_on_the_list(env: Environment) -> None:
    assert screen_of(env) == "List"


def test_list_recent_conversations_pages_latest_first(env: Environment) -> None:
    page = ok(env.call("user", "list_recent_conversations", {"limit": 3}))
    assert [c["conversation_id"] for c in page["conversations"]] == RECENT_ORDER[:3]
    assert page["total"] == 6
    family = page["conversations"][0]
    assert family["title"] == "Family"
    assert family["is_group"] is True
    assert [p["name"] for p in family["participants"]] == ["Sam Rivera", "Carol Chen", "Hiro Tanaka"]
    assert family["participants"][0]["is_current_user"] is True
    assert family["last_message"]["sender_name"] == "Hiro Tanaka"
    assert family["last_message"]["content"] == "I'll book the Italian place"
    page = ok(env.call("user", "list_recent_conversations", {"offset": 3}))
    assert [c["conversation_id"] for c in page["conversations"]] == RECENT_ORDER[3:]
    assert screen_of(env) == "List"


def test_search_conversations(env: Environment) -> None:
    def found(query: str) -> list[str]:
        return [c["conversation_id"] for c in ok(env.call("user", "search_conversations", {"query": query}))]

    assert found("rent") == ["c-bob"]
    assert found("HIKING") == ["g-hike"]  # title
    assert found("chen") == ["g-family", "c-alice", "g-work"]  # participant names, latest first
    assert found("alice lease") == ["c-alice"]  # every word, anywhere in the conversation
    assert found("summit.jpg") == ["g-hike"]  # attachment name
    assert found("sam") == []  # the user's own name matches nothing by itself
    assert found("squash pineapple") == []
    hits = ok(env.call("user", "search_conversations", {"query": "lease"}))
    assert [m["message_id"] for m in hits[0]["matching_messages"]] == ["m-a2"]
    assert screen_of(env) == "List"


def test_search_with_empty_query_is_an_error(env: Environment) -> None:
    err(env.call("user", "search_conversations", {"query": "  "}), "empty")
    assert screen_of(env) == "List"


def test_open_conversation_goes_to_opened(env: Environment) -> None:
    shown = ok(env.call("user", "open_conversation", {"conversation_id": "c-alice"}))
    assert screen_of(env) == "Opened"
    assert [m["message_id"] for m in shown["messages"]] == ["m-a3", "m-a2", "m-a1"]
    assert shown["messages"][0]["attachment"] == "/Documents/lease.pdf"
    assert shown["messages"][1]["from_current_user"] is True
    assert env.system.current_screen().conversation_id == "c-alice"


def test_open_unknown_conversation_is_an_error_and_stays(env: Environment) -> None:
    before = env.snapshot()
    err(env.call("user", "open_conversation", {"conversation_id": "c-nobody"}), "no conversation", "c-nobody")
    assert screen_of(env) == "List"
    assert env.snapshot() == before


# -- Opened screen -----------------------------------------------------------------------------------


def test_read_messages_pages_newest_first(env: Environment) -> None:
    ok(env.call("user", "open_conversation", {"conversation_id": "c-alice"}))
    page = ok(env.call("user", "read_messages", {"limit": 2}))
    assert [m["message_id"] for m in page["messages"]] == ["m-a3", "m-a2"]
    assert page["total_messages"] == 3
    page = ok(env.call("user", "read_messages", {"offset": 2}))
    assert [m["content"] for m in page["messages"]] == ["Hey! Did you get a chance to look at the flat?"]
    assert page["messages"][0]["sender_name"] == "Alice Chen"
    assert screen_of(env) == "Opened"
    err(env.call("user", "read_messages", {"limit": 0}), "limit")


def test_send_message_in_one_to_one_conversation(env: Environment) -> None:
    ok(env.call("user", "open_conversation", {"conversation_id": "c-dev"}))
    env.advance(timedelta(minutes=5))
    sent = ok(env.call("user", "send_message", {"content": "  Yes, 7pm at the club  "}))
    assert screen_of(env) == "Opened"
    assert env.log[-1].kind == "write"
    assert sent["content"] == "Yes, 7pm at the club"
    assert sent["from_current_user"] is True
    message = last_message(env, "c-dev")
    assert message["sender_id"] == "u-sam"
    assert message["content"] == "Yes, 7pm at the club"
    assert message["timestamp"].startswith("2025-03-03T09:05")
    assert len(conversations(env)) == 6  # no new conversation
    assert conversations(env)["c-dev"]["last_updated"].startswith("2025-03-03T09:05")
    assert call(env, "list_recent_conversations", limit=1)["conversations"][0]["conversation_id"] == "c-dev"


def test_send_message_in_group_conversation(env: Environment) -> None:
    ok(env.call("user", "open_conversation", {"conversation_id": "g-hike"}))
    sent = ok(
        env.call("user", "send_message", {"content": "Agenda attached", "attachment": "Documents/agenda.txt"})
    )
    assert screen_of(env) == "Opened"
    assert env.log[-1].kind == "write"
    assert sent["attachment"] == "/Documents/agenda.txt"
    message = last_message(env, "g-hike")
    assert (message["sender_id"], message["content"]) == ("u-sam", "Agenda attached")
    assert message["attachment"] == "/Documents/agenda.txt"
    assert len(conversations(env)["g-hike"]["messages"]) == 3


def test_send_attachment_only_from_opened(env: Environment) -> None:
    ok(env.call("user", "open_conversation", {"conversation_id": "c-bob"}))
    ok(env.call("user", "send_message", {"content": "", "attachment": "/Documents/lease.pdf"}))
    assert last_message(env, "c-bob")["attachment"] == "/Documents/lease.pdf"
    assert last_message(env, "c-bob")["content"] == ""


@pytest.mark.parametrize(
    ("conversation_id", "args", "message"),
    [
        ("c-bob", {"content": "   "}, "empty"),
        ("g-family", {"content": ""}, "empty"),
        ("c-bob", {"content": "see attached", "attachment": "/Documents/missing.pdf"}, "no file"),
        ("g-family", {"content": "see attached", "attachment": "/../etc/passwd"}, "leaves"),
    ],
)
def test_send_errors_from_opened_change_nothing(
    env: Environment, conversation_id: str, args: dict, message: str
) -> None:
    ok(env.call("user", "open_conversation", {"conversation_id": conversation_id}))
    before = env.snapshot()
    err(env.call("user", "send_message", args), message)
    assert env.snapshot() == before
    assert screen_of(env) == "Opened"


# -- agent API ---------------------------------------------------------------------------------------


def test_agent_read_api(env: Environment) -> None:
    page = call(env, "list_recent_conversations")
    assert [c["conversation_id"] for c in page["conversations"]] == RECENT_ORDER[:5]
    assert page["total"] == 6
    page = call(env, "list_conversations_by_participant", user_id="u-alice")
    assert [c["conversation_id"] for c in page["conversations"]] == ["c-alice", "g-work"]
    assert page["total"] == 2
    page = call(env, "list_conversations_by_participant", user_id="u-dev", offset=1, limit=1)
    assert [c["conversation_id"] for c in page["conversations"]] == ["g-work"]
    assert call(env, "list_conversations_by_participant", user_id="u-emma")["total"] == 0
    read = call(env, "read_conversation", conversation_id="g-hike", limit=1)
    assert read["title"] == "Hiking crew"
    assert [m["sender_name"] for m in read["messages"]] == ["Inès Moreau"]
    assert read["total_messages"] == 2
    assert [c["conversation_id"] for c in call(env, "search", query="birthday")] == ["g-family"]
    assert call(env, "get_user_id", user_name="  alice CHEN ") == "u-alice"
    assert call(env, "get_user_id", user_name="Sam Rivera") == "u-sam"
    assert call(env, "get_user_name_from_id", user_id="u-ines") == "Inès Moreau"


def test_agent_send_message_to_existing_and_new_one_to_one(env: Environment) -> None:
    sent = call(env, "send_message", user_id="u-bob", content="Rent sent")
    # the result says whom it went to, where, and carries the conversation's id
    assert sent["id"] == "c-bob"
    assert sent["done"].startswith("Sent ") and "to Bob" in sent["done"] and "c-bob" in sent["done"]
    assert last_message(env, "c-bob")["content"] == "Rent sent"
    new_id = call(env, "send_message", user_id="u-emma", content="Welcome to the team!")["id"]
    created = conversations(env)[new_id]
    assert created["participant_ids"] == ["u-sam", "u-emma"]
    assert created["is_group"] is False
    assert [m["content"] for m in created["messages"]] == ["Welcome to the team!"]
    assert created["messages"][0]["sender_id"] == "u-sam"
    # the next message to Emma goes to the same conversation
    assert (
        call(env, "send_message", user_id="u-emma", content="Lunch?", attachment="/Documents/agenda.txt")[
            "id"
        ]
        == new_id
    )
    assert last_message(env, new_id)["attachment"] == "/Documents/agenda.txt"


def test_agent_group_api(env: Environment) -> None:
    group = call(
        env, "create_group_conversation", user_ids=["u-bob", "u-emma", "u-bob", "u-sam"], title="Flat"
    )["id"]
    created = conversations(env)[group]
    assert created["participant_ids"] == ["u-sam", "u-bob", "u-emma"]
    assert created["is_group"] is True
    assert created["title"] == "Flat"
    assert created["messages"] == []
    assert call(env, "list_recent_conversations", limit=1)["conversations"][0]["conversation_id"] == group
    message_id = call(env, "send_message_to_group_conversation", conversation_id=group, content="Hello both")[
        "id"
    ]
    assert last_message(env, group)["message_id"] == message_id
    call(env, "send_message_to_group_conversation", conversation_id="c-dev", content="works in 1:1 too")
    assert last_message(env, "c-dev")["content"] == "works in 1:1 too"

    assert "Added Dev Patel" in call(
        env, "add_participant_to_conversation", conversation_id=group, user_id="u-dev"
    )
    assert conversations(env)[group]["participant_ids"] == ["u-sam", "u-bob", "u-emma", "u-dev"]
    call(env, "remove_participant_from_conversation", conversation_id=group, user_id="u-bob")
    assert conversations(env)[group]["participant_ids"] == ["u-sam", "u-emma", "u-dev"]
    call(env, "change_conversation_title", conversation_id=group, title="  New flat  ")
    assert conversations(env)[group]["title"] == "New flat"
    untitled = call(env, "create_group_conversation", user_ids=["u-grace", "u-hiro"])["id"]
    assert conversations(env)[untitled]["title"] is None


def test_adding_someone_to_a_one_to_one_makes_it_a_group(env: Environment) -> None:
    result = call(env, "add_participant_to_conversation", conversation_id="c-bob", user_id="u-carol")
    assert "now a group" in result
    assert conversations(env)["c-bob"]["is_group"] is True
    # Bob no longer has a one-to-one conversation: a new one is started
    new_id = call(env, "send_message", user_id="u-bob", content="Just us")["id"]
    assert new_id != "c-bob"
    assert conversations(env)[new_id]["participant_ids"] == ["u-sam", "u-bob"]


def test_download_attachment(env: Environment) -> None:
    saved = call(env, "download_attachment", conversation_id="c-alice", message_id="m-a3")
    path = saved["id"]
    assert path == "/Downloads/lease.pdf" and "lease.pdf" in saved["done"]
    files = env.snapshot()["files"]["files"]
    assert files[path]["content"] == "Lease agreement, 14 Elm St, from April 1."
    # downloading again keeps the same copy
    assert call(env, "download_attachment", conversation_id="c-alice", message_id="m-a3")["id"] == path
    # a different file already at the name is not overwritten
    ok(env.call("env", "files__create_file", {"path": "/Photos/Saved/summit.jpg", "content": "another"}))
    saved = call(
        env, "download_attachment", conversation_id="g-hike", message_id="m-h2", path="/Photos/Saved/"
    )["id"]
    assert saved == "/Photos/Saved/summit (1).jpg"
    files = env.snapshot()["files"]["files"]
    assert files["/Photos/Saved/summit.jpg"]["content"] == "another"
    assert files[saved]["content"] == "JPEG summit photo"


@pytest.mark.parametrize(
    ("tool", "args", "message"),
    [
        ("list_recent_conversations", {"limit": 0}, "limit"),
        ("list_recent_conversations", {"offset": -1}, "offset"),
        ("list_conversations_by_participant", {"user_id": "u-zed"}, "no user with id 'u-zed'"),
        ("read_conversation", {"conversation_id": "ghost"}, "no conversation with id 'ghost'"),
        ("read_conversation", {"conversation_id": "c-bob", "limit": 101}, "limit"),
        ("search", {"query": ""}, "empty"),
        ("get_user_id", {"user_name": "Alice"}, "no user is called, alice chen"),
        ("get_user_id", {"user_name": "Grace Kimm"}, "grace kim"),
        ("get_user_id", {"user_name": " "}, "empty"),
        ("get_user_name_from_id", {"user_id": "u-alicee"}, "u-alice"),
        ("send_message", {"user_id": "u-zed", "content": "hi"}, "no user"),
        ("send_message", {"user_id": "u-sam", "content": "hi"}, "yourself"),
        ("send_message", {"user_id": "u-emma", "content": " "}, "empty"),
        ("send_message", {"user_id": "u-emma", "content": "hi", "attachment": "/nope.txt"}, "no file"),
        ("send_message_to_group_conversation", {"conversation_id": "ghost", "content": "hi"}, "ghost"),
        ("send_message_to_group_conversation", {"conversation_id": "g-hike", "content": ""}, "empty"),
        ("create_group_conversation", {"user_ids": ["u-bob"]}, "at least two"),
        ("create_group_conversation", {"user_ids": ["u-bob", "u-sam"]}, "at least two"),
        ("create_group_conversation", {"user_ids": ["u-bob", "u-bob"]}, "at least two"),
        ("create_group_conversation", {"user_ids": ["u-bob", "u-zed"]}, "u-zed"),
        ("add_participant_to_conversation", {"conversation_id": "g-hike", "user_id": "u-grace"}, "already"),
        ("add_participant_to_conversation", {"conversation_id": "g-hike", "user_id": "u-zed"}, "no user"),
        ("add_participant_to_conversation", {"conversation_id": "ghost", "user_id": "u-bob"}, "ghost"),
        ("remove_participant_from_conversation", {"conversation_id": "g-hike", "user_id": "u-bob"}, "not in"),
        ("remove_participant_from_conversation", {"conversation_id": "g-hike", "user_id": "u-sam"}, "owner"),
        (
            "remove_participant_from_conversation",
            {"conversation_id": "c-bob", "user_id": "u-bob"},
            "one-to-one",
        ),
        ("change_conversation_title", {"conversation_id": "c-bob", "title": "Landlord"}, "one-to-one"),
        ("change_conversation_title", {"conversation_id": "g-hike", "title": " "}, "empty"),
        ("change_conversation_title", {"conversation_id": "ghost", "title": "X"}, "ghost"),
        ("download_attachment", {"conversation_id": "c-alice", "message_id": "m-a1"}, "no attachment"),
        ("download_attachment", {"conversation_id": "c-alice", "message_id": "m-h2"}, "no message"),
        (
            "download_attachment",
            {"conversation_id": "c-alice", "message_id": "m-a3", "path": "/../x"},
            "leaves",
        ),
    ],
)
def test_agent_api_errors_change_nothing(env: Environment, tool: str, args: dict, message: str) -> None:
    before = env.snapshot()
    err(env.call("assistant", f"messaging__{tool}", args, mode="execute"), *message.split(", "))
    assert env.snapshot() == before


def test_removing_the_last_other_participant_is_refused(env: Environment) -> None:
    call(env, "remove_participant_from_conversation", conversation_id="g-family", user_id="u-hiro")
    assert conversations(env)["g-family"]["participant_ids"] == ["u-sam", "u-carol"]
    assert conversations(env)["g-family"]["is_group"] is True
    before = env.snapshot()
    err(
        env.call(
            "assistant",
            "messaging__remove_participant_from_conversation",
            {"conversation_id": "g-family", "user_id": "u-carol"},
            mode="execute",
        ),
        "last other",
    )
    assert env.snapshot() == before


def test_download_of_a_deleted_file_changes_nothing(env: Environment) -> None:
    env.apps["files"].state.files.pop("/Documents/lease.pdf")
    before = env.snapshot()
    err(
        env.call(
            "assistant",
            "messaging__download_attachment",
            {"conversation_id": "c-alice", "message_id": "m-a3"},
            mode="execute",
        ),
        "no file",
    )
    assert env.snapshot() == before


def test_write_tools_are_not_available_in_observe_mode(env: Environment) -> None:
    err(
        env.call("assistant", "messaging__send_message", {"user_id": "u-bob", "content": "hi"}),
        "execute mode",
    )
    err(
        env.call(
            "assistant", "messaging__receive_message", {"sender": "Bob", "content": "hi"}, mode="execute"
        )
    )


# -- the world: receive_message ----------------------------------------------------------------------


def test_receive_from_known_sender_goes_to_the_one_to_one(env: Environment) -> None:
    env.advance(timedelta(minutes=2))
    got = receive(env, sender="alice chen", content="Did you sign it?")
    assert got == {"conversation_id": "c-alice", "message_id": got["message_id"], "sender_id": "u-alice"}
    message = last_message(env, "c-alice")
    assert (message["message_id"], message["sender_id"]) == (got["message_id"], "u-alice")
    assert message["timestamp"].startswith("2025-03-03T09:02")
    assert call(env, "list_recent_conversations", limit=1)["conversations"][0]["conversation_id"] == "c-alice"
    assert len(state(env)["users"]) == len(USERS)
    # a user id works as sender too
    assert receive(env, sender="u-bob", content="Got it, thanks")["conversation_id"] == "c-bob"


def test_receive_from_unknown_sender_creates_user_and_conversation(env: Environment) -> None:
    got = receive(env, sender="Zoe Martin", content="Hi, this is Zoe from the gym", message_id="m-zoe")
    assert got["message_id"] == "m-zoe"
    users = state(env)["users"]
    assert users[got["sender_id"]] == "Zoe Martin"
    conversation = conversations(env)[got["conversation_id"]]
    assert conversation["participant_ids"] == ["u-sam", got["sender_id"]]
    assert conversation["is_group"] is False
    assert call(env, "get_user_id", user_name="zoe martin") == got["sender_id"]
    # a second message from her lands in the same place, and ids are deterministic
    again = receive(env, sender="Zoe Martin", content="See you Tuesday")
    assert again["conversation_id"] == got["conversation_id"]
    other = make_env(["messaging"], SEED)
    assert (
        ok(other.call("env", "messaging__receive_message", {"sender": "Zoe Martin", "content": "x"}))[
            "sender_id"
        ]
        == got["sender_id"]
    )


def test_receive_with_conversation_id_adds_the_sender(env: Environment) -> None:
    got = receive(env, sender="Grace Kim", content="Same time next week?", conversation_id="g-hike")
    assert got["conversation_id"] == "g-hike"
    assert conversations(env)["g-hike"]["participant_ids"] == ["u-sam", "u-grace", "u-farid", "u-ines"]
    got = receive(env, sender="Emma Larsen", content="Can I join?", conversation_id="g-hike")
    assert conversations(env)["g-hike"]["participant_ids"][-1] == "u-emma"
    assert last_message(env, "g-hike")["sender_id"] == "u-emma"
    # a newcomer posting in a one-to-one makes it a group
    receive(env, sender="Bob Okafor", content="Hi both", conversation_id="c-dev")
    assert conversations(env)["c-dev"]["is_group"] is True


def test_receive_with_group_title(env: Environment) -> None:
    got = receive(env, sender="Carol Chen", content="Bring dessert!", group_title="family")
    assert got["conversation_id"] == "g-family"
    assert len(conversations(env)["g-family"]["participant_ids"]) == 3
    got = receive(env, sender="Hiro", content="Who's in?", group_title="Family")  # new person joins
    assert conversations(env)["g-family"]["participant_ids"][-1] == got["sender_id"]
    assert state(env)["users"][got["sender_id"]] == "Hiro"
    created = receive(env, sender="Maya", content="Snacks on Thursday?", group_title="Book Club")
    group = conversations(env)[created["conversation_id"]]
    assert group["title"] == "Book Club"
    assert group["is_group"] is True
    assert group["participant_ids"] == ["u-sam", created["sender_id"]]
    again = receive(env, sender="Noor", content="I'll bring tea", group_title="Book Club")
    assert again["conversation_id"] == created["conversation_id"]
    assert len(conversations(env)[created["conversation_id"]]["participant_ids"]) == 3


def test_receive_notifies_user_truncated_and_assistant_in_full(env: Environment) -> None:
    env.user_view()
    env.assistant_observation()
    got = receive(env, sender="Bob Okafor", content=LONG)
    (user_copy,) = env.user_view().notifications
    assert "Messages: New message from Bob Okafor" in user_copy
    assert "plumber" in user_copy
    assert "PINEAPPLE" not in user_copy
    assert got["message_id"] not in user_copy
    (assistant_copy,) = env.assistant_observation().notifications
    assert "New message from Bob Okafor" in assistant_copy
    assert "PINEAPPLE" in assistant_copy
    assert got["message_id"] in assistant_copy
    assert "c-bob" in assistant_copy


def test_group_notification_names_the_group(env: Environment) -> None:
    env.user_view()
    receive(env, sender="Farid Haddad", content="Boots on!", group_title="Hiking crew")
    receive(env, sender="Dev Patel", content="Ordering now", conversation_id="g-work")
    first, second = env.user_view().notifications
    assert "New message from Farid Haddad in Hiking crew: Boots on!" in first
    assert "New message from Dev Patel in Alice Chen, Dev Patel: Ordering now" in second


def test_receive_with_attachment(env: Environment) -> None:
    got = receive(env, sender="Inès Moreau", content="", attachment="/Photos/summit.jpg")
    message = last_message(env, got["conversation_id"])
    assert message["attachment"] == "/Photos/summit.jpg"
    (assistant_copy,) = env.assistant_observation().notifications
    assert "summit.jpg" in assistant_copy


@pytest.mark.parametrize(
    ("args", "message"),
    [
        ({"sender": "Bob Okafor", "content": "  "}, "empty"),
        ({"sender": " ", "content": "hi"}, "sender is empty"),
        ({"sender": "Sam Rivera", "content": "hi"}, "owner"),
        ({"sender": "u-sam", "content": "hi"}, "owner"),
        ({"sender": "Stranger", "content": "hi", "conversation_id": "ghost"}, "ghost"),
        ({"sender": "Stranger", "content": "hi", "message_id": "m-a1"}, "already exists"),
        ({"sender": "Stranger", "content": "hi", "message_id": " "}, "message id is empty"),
        ({"sender": "Stranger", "content": "hi", "attachment": "/nope.pdf"}, "no file"),
        ({"sender": "Stranger", "content": "hi", "group_title": "New group", "attachment": "/x"}, "no file"),
        ({"content": "hi"}, "missing required argument 'sender'"),
    ],
)
def test_receive_errors_change_nothing(env: Environment, args: dict, message: str) -> None:
    env.user_view()
    before = env.snapshot()
    err(env.call("env", "messaging__receive_message", args), message)
    assert env.snapshot() == before
    assert env.user_view().notifications == []


def test_received_message_shows_on_the_opened_screen(env: Environment) -> None:
    ok(env.call("user", "open_conversation", {"conversation_id": "c-dev"}))
    receive(env, sender="Dev Patel", content="Court 3 is booked")
    page = ok(env.call("user", "read_messages", {"limit": 1}))
    assert page["messages"][0]["content"] == "Court 3 is booked"
    ok(env.call("user", "send_message", {"content": "Great"}))
    assert [m["content"] for m in conversations(env)["c-dev"]["messages"][-2:]] == [
        "Court 3 is booked",
        "Great",
    ]


def test_opened_conversation_can_browse_files_to_send(env: Environment) -> None:
    conversation = ok(env.call("user", "list_recent_conversations"))["conversations"][0]["conversation_id"]
    ok(env.call("user", "open_conversation", {"conversation_id": conversation}))
    photos = ok(env.call("user", "browse_files", {"directory": "/Photos"}))
    assert [e["path"] for e in photos] == ["/Photos/summit.jpg"]
    assert screen_of(env) == "Opened"
    err(env.call("user", "browse_files", {"directory": "/Nowhere"}), "no directory")


def test_received_messages_are_unread_until_the_user_opens_the_conversation(env: Environment) -> None:
    sent = ok(env.call("env", "messaging__receive_message", {"sender": "Bob Lee", "content": "Ping"}))
    conversation = sent["conversation_id"]
    listed = ok(env.call("assistant", "messaging__list_recent_conversations", {}, mode="observe"))
    row = next(c for c in listed["conversations"] if c["conversation_id"] == conversation)
    assert row["unread"] == 1
    assert env.user_view().screen_update["conversations"][0]["unread"] == 1  # the list on screen shows it
    opened = env.call("user", "open_conversation", {"conversation_id": conversation})
    assert opened.ok and opened.entry is not None and opened.entry.kind == "ui"  # seeing is not writing
    assert state(env)["conversations"][conversation]["unread"] == 0
    ok(env.call("env", "messaging__receive_message", {"sender": "Bob Lee", "content": "Again"}))
    assert state(env)["conversations"][conversation]["unread"] == 1
    ok(env.call("user", "read_messages", {}))
    assert state(env)["conversations"][conversation]["unread"] == 0


def test_group_writes_say_who_is_in_the_conversation(env: Environment) -> None:
    group = call(env, "create_group_conversation", user_ids=["u-bob", "u-emma"], title="Flat")
    assert group["done"] == f"Started conversation {group['id']} ('Flat') with Bob Okafor and Emma Larsen."
    sent = call(env, "send_message_to_group_conversation", conversation_id=group["id"], content="Hi")
    assert (
        sent["done"]
        == f"Sent {sent['id']} in conversation {group['id']} ('Flat') to Bob Okafor and Emma Larsen."
    )
