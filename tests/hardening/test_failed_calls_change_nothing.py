"""A tool call that fails changes nothing, and leaves state that passes its own validation."""

from __future__ import annotations

from typing import Any

from pare.env import Environment
from tests.conftest import err, make_env, ok

LEASE = "/Documents/lease.pdf"
DEPOSIT = "/Documents/deposit.pdf"
SEED: dict[str, Any] = {
    "files": {"files": {LEASE: {"content": "Lease."}, DEPOSIT: {"content": "Deposit."}}},
    "email": {
        "user_email": "me@pare.example",
        "emails": {
            "e-lease": {
                "email_id": "e-lease",
                "sender": "landlord@pare.example",
                "subject": "Lease",
                "content": "Both attached.",
                "attachments": [LEASE, DEPOSIT],
                "timestamp": "2025-01-06T08:00:00Z",
            }
        },
    },
}


def call(env: Environment, tool: str, **args: Any) -> Any:
    return env.call("assistant", tool, args, mode="execute")


def files_state(env: Environment) -> dict[str, Any]:
    state: dict[str, Any] = env.snapshot()["files"]
    return state


def test_downloading_attachments_is_all_or_nothing() -> None:
    env = make_env(["email"], SEED)
    # The second attachment's name is taken by a folder: the first must not be saved on its own.
    ok(call(env, "files__make_directory", path="/Downloads/deposit.pdf"))
    saved = ok(call(env, "email__download_attachments", email_id="e-lease"))
    # a free name, not a failure
    assert saved["paths"] == ["/Downloads/lease.pdf", "/Downloads/deposit (2).pdf"]

    env = make_env(["email"], SEED)
    ok(call(env, "files__write_file", path="/Downloads", content="a file where the folder should be"))
    before = files_state(env)
    err(call(env, "email__download_attachments", email_id="e-lease"), "is a file")
    assert files_state(env) == before


def test_a_directory_cannot_take_a_files_path() -> None:
    env = make_env(["email"], SEED)
    before = files_state(env)
    err(call(env, "files__make_directory", path=LEASE), "is a file")
    assert files_state(env) == before
    ok(call(env, "files__write_file", path=LEASE, content="Lease, signed."))  # still an ordinary file
    type(env.apps["files"].state).model_validate(env.apps["files"].state.model_dump())


def test_an_attachment_whose_file_was_deleted_says_so() -> None:
    env = make_env(["email"], SEED)
    ok(call(env, "files__delete", path=DEPOSIT))
    err(
        call(env, "email__download_attachments", email_id="e-lease"), f"{DEPOSIT} attached to email 'e-lease'"
    )
    assert "/Downloads/lease.pdf" not in files_state(env)["files"]
