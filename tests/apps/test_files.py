from __future__ import annotations

from typing import Any

import pytest

from pare.apps.files import normalize_path
from pare.env import Environment
from pare.errors import ToolError, UserInputError
from tests.conftest import err, make_env, ok

SEED = {
    "files": {
        "files": {
            "/Documents/lease.txt": {"content": "Lease for flat 4B."},
            "/Documents/Taxes/2024.txt": {"content": "Refund: 312.50"},
            "/Downloads/menu.txt": {"content": "Soup, bread"},
        },
        "directories": ["/Photos"],
    }
}


@pytest.fixture
def env() -> Environment:
    return make_env([], SEED)


def call(env: Environment, tool: str, **args: Any) -> Any:
    return ok(env.call("assistant", f"files__{tool}", args, mode="execute"))


def files(env: Environment) -> dict[str, Any]:
    return env.snapshot()["files"]["files"]


@pytest.mark.parametrize(
    ("path", "expected"),
    [
        ("/Documents/lease.txt", "/Documents/lease.txt"),
        ("Documents//./lease.txt", "/Documents/lease.txt"),
        ("/Documents/Taxes/../lease.txt", "/Documents/lease.txt"),
        ("/", "/"),
    ],
)
def test_paths_are_normalised_inside_the_sandbox(path: str, expected: str) -> None:
    assert normalize_path(path) == expected


@pytest.mark.parametrize(
    ("path", "message"),
    [
        ("../etc/passwd", "leaves the phone's file storage"),
        ("/Documents/../../etc/passwd", "leaves"),
        ("~/secrets.txt", "outside the phone's file storage"),
        ("C:/Windows/system.ini", "outside"),
        ("file:///etc/passwd", "outside"),
        ("https://example.com/x", "outside"),
        ("\\\\server\\share", "separator"),
        ("/Documents/a\x00.txt", "control characters"),
        ("", "empty"),
        ("/" + "a" * 300, "longer than 255"),
    ],
)
def test_escapes_are_refused_by_every_tool(env: Environment, path: str, message: str) -> None:
    with pytest.raises(ToolError, match=message):
        normalize_path(path)
    before = env.snapshot()
    for tool, args in [
        ("read_file", {"path": path}),
        ("write_file", {"path": path, "content": "x"}),
        ("list_directory", {"path": path}),
        ("delete", {"path": path}),
        ("move", {"source": "/Downloads/menu.txt", "destination": path}),
        ("make_directory", {"path": path}),
    ]:
        if path == "" and tool == "list_directory":
            continue
        err(env.call("assistant", f"files__{tool}", args, mode="execute"))
    assert env.snapshot() == before


def test_list_directory_shows_direct_children_directories_first(env: Environment) -> None:
    top = call(env, "list_directory")
    assert [(e["name"], e["type"]) for e in top] == [
        ("Documents", "directory"),
        ("Downloads", "directory"),
        ("Photos", "directory"),
    ]
    docs = call(env, "list_directory", path="/Documents")
    assert [(e["name"], e["type"], e["size"]) for e in docs] == [
        ("Taxes", "directory", None),
        ("lease.txt", "file", 18),
    ]
    assert call(env, "list_directory", path="/Photos") == []


def test_list_files_is_recursive(env: Environment) -> None:
    assert call(env, "list_files", directory="/Documents") == [
        "/Documents/Taxes/2024.txt",
        "/Documents/lease.txt",
    ]
    assert len(call(env, "list_files")) == 3


def test_read_and_info(env: Environment) -> None:
    assert call(env, "read_file", path="Documents/Taxes/2024.txt") == "Refund: 312.50"
    assert call(env, "get_file_info", path="/Downloads/menu.txt")["size"] == 11


def test_write_creates_parents_and_respects_overwrite(env: Environment) -> None:
    written = call(env, "write_file", path="/Notes/new/today.txt", content="hi")
    assert written == {"done": "Created /Notes/new/today.txt (2 characters).", "id": "/Notes/new/today.txt"}
    assert call(env, "list_directory", path="/Notes")[0]["name"] == "new"
    assert call(env, "write_file", path="/Notes/new/today.txt", content="again")["done"].startswith(
        "Replaced"
    )
    assert files(env)["/Notes/new/today.txt"]["content"] == "again"
    err(
        env.call(
            "assistant",
            "files__write_file",
            {"path": "/Notes/new/today.txt", "content": "x", "overwrite": False},
            mode="execute",
        ),
        "already exists",
    )


def test_make_directory(env: Environment) -> None:
    assert call(env, "make_directory", path="/Music/Jazz")["id"] == "/Music/Jazz"
    assert "/Music/Jazz" in env.snapshot()["files"]["directories"]
    assert call(env, "list_directory", path="/Music/Jazz") == []


def test_move_file_and_directory(env: Environment) -> None:
    moved = call(env, "move", source="/Downloads/menu.txt", destination="/Documents")
    assert moved == {"done": "Moved /Downloads/menu.txt to /Documents/menu.txt.", "id": "/Documents/menu.txt"}
    assert "/Downloads/menu.txt" not in files(env)
    assert (
        call(env, "move", source="/Documents/Taxes", destination="/Archive/Taxes")["id"] == "/Archive/Taxes"
    )
    assert "/Archive/Taxes/2024.txt" in files(env)
    assert "/Documents/Taxes/2024.txt" not in files(env)
    assert call(env, "move", source="/Photos", destination="/Pictures")["id"] == "/Pictures"
    assert "/Pictures" in env.snapshot()["files"]["directories"]


def test_copy_file(env: Environment) -> None:
    copied = call(env, "copy_file", source="/Downloads/menu.txt", destination="/Photos")
    assert copied == {"done": "Copied /Downloads/menu.txt to /Photos/menu.txt.", "id": "/Photos/menu.txt"}
    assert files(env)["/Photos/menu.txt"]["content"] == "Soup, bread"
    assert "/Downloads/menu.txt" in files(env)


def test_delete_file_and_directories(env: Environment) -> None:
    call(env, "delete", path="/Downloads/menu.txt")
    assert "/Downloads/menu.txt" not in files(env)
    call(env, "delete", path="/Photos")
    assert "/Photos" not in env.snapshot()["files"]["directories"]
    call(env, "delete", path="/Documents", recursive=True)
    assert files(env) == {}


@pytest.mark.parametrize(
    ("tool", "args", "message"),
    [
        ("read_file", {"path": "/nope.txt"}, "no file at /nope.txt"),
        ("read_file", {"path": "/Documents"}, "is a directory"),
        ("list_directory", {"path": "/Documents/lease.txt"}, "is a file"),
        ("list_directory", {"path": "/Nowhere"}, "no directory"),
        ("write_file", {"path": "/Documents", "content": "x"}, "is a directory"),
        ("write_file", {"path": "/Documents/lease.txt/x", "content": "x"}, "is a file"),
        ("write_file", {"path": "/", "content": "x"}, "needs a name"),
        ("make_directory", {"path": "/Documents"}, "already exists"),
        ("make_directory", {"path": "/Documents/lease.txt/sub"}, "is a file"),
        ("move", {"source": "/nope", "destination": "/x"}, "nothing to move"),
        ("move", {"source": "/Documents", "destination": "/Documents/Taxes/inner"}, "inside itself"),
        ("move", {"source": "/Downloads/menu.txt", "destination": "/Documents/lease.txt"}, "already exists"),
        ("move", {"source": "/", "destination": "/x"}, "root cannot be moved"),
        ("copy_file", {"source": "/Documents/lease.txt", "destination": "/Documents"}, "already exists"),
        ("delete", {"path": "/Documents"}, "not empty"),
        ("delete", {"path": "/"}, "cannot be deleted"),
        ("delete", {"path": "/ghost.txt"}, "nothing to delete"),
        ("get_file_info", {"path": "/ghost.txt"}, "no file"),
    ],
)
def test_errors_change_nothing(env: Environment, tool: str, args: dict[str, Any], message: str) -> None:
    before = env.snapshot()
    err(env.call("assistant", f"files__{tool}", args, mode="execute"), message)
    assert env.snapshot() == before


def test_world_creates_files(env: Environment) -> None:
    assert ok(
        env.call("env", "files__create_file", {"path": "/Downloads/ticket.txt", "content": "Row 5"})
    ) == ("/Downloads/ticket.txt")
    assert files(env)["/Downloads/ticket.txt"]["content"] == "Row 5"


def test_user_has_no_file_screens_and_assistant_has_no_env_tools(env: Environment) -> None:
    assert "files" not in env.system.openable_apps()
    err(env.call("user", "open_app", {"app_name": "files"}), "no app called 'files'")
    assert "files__create_file" not in {t.name for t in env.assistant_tools("execute")}
    assert {"files__read_file", "files__list_directory"} <= {t.name for t in env.assistant_tools("observe")}


@pytest.mark.parametrize(
    "seed",
    [
        {"files": {"Documents/a.txt": {"content": "x"}}},
        {"files": {"/../a.txt": {"content": "x"}}},
        {"directories": ["/ok", "../bad"]},
    ],
)
def test_seed_paths_must_be_canonical_and_inside(seed: dict[str, Any]) -> None:
    with pytest.raises(UserInputError, match="seed data of app 'files'"):
        make_env([], {"files": seed})
