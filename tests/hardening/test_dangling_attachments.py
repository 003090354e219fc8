"""Attachments are paths in Files: moving or deleting an attached file says what it leaves dangling, and
downloading or forwarding a dangling attachment is a clear error that changes nothing."""

from __future__ import annotations

from typing import Any

import pytest

from pare.env import Environment
from tests.conftest import err, make_env, ok

SEED: dict[str, Any] = {
    "files": {
        "files": {"/Documents/lease.pdf": {"content": "lease"}, "/Documents/other.txt": {"content": "x"}}
    },
    "email": {
        "emails": {
            "e-1": {
                "email_id": "e-1",
                "sender": "agent@lets.example",
                "subject": "Your lease",
                "timestamp": "2025-03-02T10:00:00Z",
                "attachments": ["/Documents/lease.pdf"],
            }
        }
    },
    "notes": {
        "notes": {
            "n-1": {
                "note_id": "n-1",
                "title": "Flat",
                "created_at": "2025-03-01T10:00:00Z",
                "updated_at": "2025-03-01T10:00:00Z",
                "attachments": ["/Documents/lease.pdf"],
            }
        }
    },
}


@pytest.fixture
def env() -> Environment:
    return make_env(["email", "notes"], SEED)


def execute(env: Environment, tool: str, **args: Any) -> Any:
    return env.call("assistant", tool, args, mode="execute")


def test_deleting_an_attached_file_names_what_now_points_at_nothing(env: Environment) -> None:
    said = ok(execute(env, "files__delete", path="/Documents/lease.pdf"))
    assert said.startswith("Deleted file /Documents/lease.pdf.")
    assert "email 'e-1'" in said and "note 'n-1'" in said and "missing" in said


def test_moving_an_attached_folder_names_what_now_points_at_nothing(env: Environment) -> None:
    moved = ok(execute(env, "files__move", source="/Documents", destination="/Archive"))
    assert moved["id"] == "/Archive" and "email 'e-1'" in moved["done"] and "missing" in moved["done"]


def test_moving_an_unattached_file_answers_with_the_move_only(env: Environment) -> None:
    moved = ok(execute(env, "files__move", source="/Documents/other.txt", destination="/other.txt"))
    assert moved == {"done": "Moved /Documents/other.txt to /other.txt.", "id": "/other.txt"}


@pytest.mark.parametrize(
    ("tool", "args"),
    [
        ("email__download_attachments", {"email_id": "e-1"}),
        ("email__forward_email", {"email_id": "e-1", "recipients": ["sam@home.example"]}),
    ],
)
def test_a_dangling_attachment_cannot_be_downloaded_or_forwarded(
    env: Environment, tool: str, args: dict[str, Any]
) -> None:
    ok(execute(env, "files__delete", path="/Documents/lease.pdf"))
    before = env.snapshot()
    err(execute(env, tool, **args), "/documents/lease.pdf attached to email 'e-1' is no longer in files")
    assert env.snapshot() == before
