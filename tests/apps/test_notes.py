from __future__ import annotations

import random
from datetime import timedelta
from typing import Any

import pytest

from pare.apps.text import PAGE
from pare.env import Environment
from pare.env.random_walk import RandomUser
from pare.errors import UserInputError
from tests.conftest import err, make_env, ok, screen_of

PLAN = "/Documents/floor_plan.pdf"
LEASE = "/Documents/lease.pdf"
PASSPORT = "/Documents/passport_scan.pdf"
WHITEBOARD = "/Photos/whiteboard.jpg"
RECIPE = "/Downloads/recipe_card.txt"
BUDGET = "/Documents/budget.xlsx"
FILES = {
    PLAN: {"content": "Floor plan, 12 Elm Street, 2nd floor: two bedrooms, one bath."},
    LEASE: {"content": "Residential lease, 12 Elm Street. Rent: 1,450 per month."},
    PASSPORT: {"content": "Passport scan, expires 2031-05-14."},
    WHITEBOARD: {"content": "Photo of the Q1 roadmap whiteboard."},
    RECIPE: {"content": "Pasta al limone: spaghetti, lemons, parmesan, butter."},
    BUDGET: {"content": "Household budget, March."},
}


def note(
    note_id: str,
    title: str,
    content: str,
    folder: str,
    created: str,
    updated: str | None = None,
    **extra: Any,
) -> dict:
    """A seed note; ``created`` and ``updated`` are "MM-DD HH:MM" in 2025, UTC."""
    return {
        "note_id": note_id,
        "title": title,
        "content": content,
        "folder": folder,
        "created_at": f"2025-{created.replace(' ', 'T')}:00Z",
        "updated_at": f"2025-{(updated or created).replace(' ', 'T')}:00Z",
        **extra,
    }


# The episode starts on Monday 2025-03-03 at 09:00 UTC. Twelve notes in "Notes" (more than a page), a
# handful per other folder, distractors that share words (two quarterly reviews, two pasta recipes, an
# untitled note), one pinned note, and an empty folder.
# fmt: off
NOTES = [
    note("note-groceries", "Groceries", "Milk\nEggs\nSpinach\nOat milk for Carol", "Notes",
         "02-20 10:00", "03-02 18:00", pinned=True),
    note("note-wifi", "Wi-Fi password", "Home network Maple-5G, password tulip-river-42", "Notes",
         "01-05 12:00"),
    note("note-parking", "Parking spot", "Level 3, spot B12, near the lifts", "Notes", "03-01 08:00",
         "03-02 20:00"),
    note("note-untitled", "", "Call back the plumber, Ivan: 555 0199", "Notes", "03-02 16:00"),
    note("note-bike", "Bike lock", "Code 4-7-1-9", "Notes", "02-10 09:00"),
    note("note-movies", "Movies to watch", "Past Lives; Perfect Days; Dune part two", "Notes", "02-12 21:00",
         "02-27 22:00"),
    note("note-todo", "To do this week", "Renew passport\nPay rent by the 5th\nBook dentist", "Notes",
         "03-01 09:00", "03-02 09:00"),
    note("note-gym", "Gym schedule", "Mon/Wed/Fri 7am, leg day on Friday", "Notes", "02-01 07:00",
         "02-15 07:30"),
    note("note-birthdays", "Birthdays", "Mum 15 March, Carol 2 April, Lena 30 May", "Notes", "01-02 10:00",
         "02-28 10:00"),
    note("note-quotes", "Quotes", "The best time to plant a tree was twenty years ago.", "Notes",
         "01-20 22:00"),
    note("note-podcasts", "Podcasts", "Hardcore History, The Daily", "Notes", "02-05 08:00", "02-25 08:00"),
    note("note-car", "Car service", "Due at 60,000 km; garage on Oak Street", "Notes", "02-14 12:00",
         "02-26 12:00"),
    note("note-apartment", "Apartment viewing checklist", "Ask about the boiler, pets and the lease term",
         "Personal", "02-25 19:00", "03-01 19:00", attachments=[PLAN, LEASE]),
    note("note-gifts", "Gift ideas for Mum", "Silk scarf, pottery class voucher, the novel Lena mentioned",
         "Personal", "02-18 20:00"),
    note("note-lisbon", "Lisbon trip", "Flight TP 238 on the 8th, seat 14C. Hotel in Alfama.", "Personal",
         "02-22 10:00", "02-28 11:00", attachments=[PASSPORT]),
    note("note-review", "Quarterly review prep", "Slides: revenue, churn, roadmap. Ask Alice for numbers.",
         "Work", "02-26 09:00", "03-02 17:00", attachments=[WHITEBOARD]),
    note("note-review-q4", "Quarterly review Q4", "Last quarter: revenue up 4%, churn flat.", "Work",
         "01-10 09:00"),
    note("note-george", "1:1 with George", "Career goals, the roadmap, conference budget", "Work",
         "02-27 14:00"),
    note("note-standup", "Standup notes", "Alice: migration done. Bob: review pending.", "Work",
         "03-03 08:30"),
    note("note-pasta", "Pasta al limone", "Spaghetti, two lemons, parmesan, butter", "Recipes",
         "02-08 19:00", attachments=[RECIPE]),
    note("note-pasta-bake", "Pasta bake", "Penne, tomato, mozzarella; 25 min at 200C", "Recipes",
         "02-09 19:00"),
    note("note-curry", "Chickpea curry", "Chickpeas, coconut milk, spinach, garam masala", "Recipes",
         "02-11 19:00"),
]
# fmt: on
FOLDERS = ["Notes", "Personal", "Work", "Recipes", "Archive"]
SEED = {
    "files": {"files": FILES},
    "notes": {"folders": FOLDERS, "notes": {n["note_id"]: n for n in NOTES}},
}
NOTES_ORDER = [
    "note-groceries",  # pinned
    "note-parking",
    "note-untitled",
    "note-todo",
    "note-birthdays",
    "note-movies",
    "note-car",
    "note-podcasts",
    "note-gym",
    "note-bike",
    "note-quotes",
    "note-wifi",
]


@pytest.fixture
def env() -> Environment:
    """The app open on the "Notes" folder (it opens on every folder's notes; most tests look at one)."""
    env = make_env(["notes"], SEED)
    ok(env.call("user", "open_app", {"app_name": "notes"}))
    ok(env.call("user", "list_folders", {}))
    ok(env.call("user", "open_folder", {"folder": "Notes"}))
    return env


def notes(env: Environment) -> dict:
    return env.snapshot()["notes"]["notes"]


def folders(env: Environment) -> list[str]:
    return env.snapshot()["notes"]["folders"]


def ids(listing: list[dict]) -> list[str]:
    return [n["note_id"] for n in listing]


def stack(env: Environment) -> list[str]:
    return [screen.label() for screen in env.system.stacks["notes"]]


def agent(env: Environment, tool: str, **args: object) -> Any:
    return ok(env.call("assistant", f"notes__{tool}", args, mode="execute"))


def user(env: Environment, action: str, **args: object) -> Any:
    return ok(env.call("user", action, args))


NOW = "2025-03-03T09:00:00Z"
LATER = "2025-03-03T10:00:00Z"


# -- seed data ---------------------------------------------------------------------------------------


def test_default_folders() -> None:
    env = make_env(["notes"])
    assert folders(env) == ["Notes", "Personal", "Work"]
    assert agent(env, "list_folders") == [
        {"name": "Notes", "note_count": 0},
        {"name": "Personal", "note_count": 0},
        {"name": "Work", "note_count": 0},
    ]


def test_seed_normalises_attachment_paths() -> None:
    seed = note("x", "Plan", "", "Notes", "03-01 10:00", attachments=["Documents//floor_plan.pdf"])
    env = make_env(["notes"], {"notes": {"notes": {"x": seed}}})
    assert notes(env)["x"]["attachments"] == [PLAN]


@pytest.mark.parametrize(
    ("data", "message"),
    [
        ({"notes": {"x": note("x", "A", "", "Music", "03-01 10:00")}}, "folder 'Music', which is not one of"),
        ({"notes": {"x": note("x", "A", "", "work", "03-01 10:00")}}, "folder 'work', which is not one of"),
        ({"notes": {"y": note("x", "A", "", "Notes", "03-01 10:00")}}, "has note_id 'x'"),
        ({"folders": ["Notes", "Work", "WORK"]}, "'WORK' is listed twice"),
        ({"folders": ["Personal", "Work"]}, "default folder 'Notes' is missing"),
        ({"folders": ["Notes", " "]}, "empty"),
        ({"notes": {"x": note("x", "A", "", "Notes", "03-01 10:00", "02-01 10:00")}}, "updated before"),
        (
            {"notes": {"x": note("x", "A", "", "Notes", "03-01 10:00", attachments=[PLAN, "/x/../" + PLAN])}},
            "attached twice",
        ),
        ({"notes": {"x": note("x", "A", "", "Notes", "03-01 10:00", attachments=["../up"])}}, "leaves"),
    ],
)
def test_seed_is_validated(data: dict, message: str) -> None:
    with pytest.raises(UserInputError, match=message):
        make_env(["notes"], {"notes": data})


# -- List --------------------------------------------------------------------------------------------


def test_opens_on_every_folders_notes_with_their_folders() -> None:
    env = make_env(["notes"], SEED)
    ok(env.call("user", "open_app", {"app_name": "notes"}))
    assert screen_of(env) == "List"
    assert stack(env) == ["List(all folders)"]
    page = user(env, "list_notes", limit=4)
    assert page["folder"] is None
    assert page["total"] == len(NOTES)
    # pinned first, then the most recently updated of any folder, each with its folder
    assert [(n["note_id"], n["folder"]) for n in page["notes"]] == [
        ("note-groceries", "Notes"),
        ("note-standup", "Work"),
        ("note-parking", "Notes"),
        ("note-review", "Work"),
    ]
    err(env.call("user", "list_notes", {"limit": 0}), "limit between 1 and 100")
    # a new note from here goes to the default folder
    assert user(env, "new_note")["folder"] == "Notes"


def test_opens_on_the_notes_of_other_folders_when_the_default_one_is_empty() -> None:
    seed = {"notes": {"notes": {"w": note("w", "Standup", "Alice: done", "Work", "03-01 10:00")}}}
    env = make_env(["notes"], seed)
    ok(env.call("user", "open_app", {"app_name": "notes"}))
    assert ids(user(env, "list_notes")["notes"]) == ["w"]


def test_show_all_notes_from_the_folders(env: Environment) -> None:
    assert stack(env) == ["List(folder='Notes')"]
    user(env, "list_folders")
    assert env.call("user", "show_all_notes", {}).value is None
    assert screen_of(env) == "List"
    assert stack(env) == ["List(all folders)"]
    assert user(env, "list_notes")["total"] == len(NOTES)


def test_list_notes_pinned_first_then_most_recently_updated(env: Environment) -> None:
    page = user(env, "list_notes")
    assert page["folder"] == "Notes"
    assert ids(page["notes"]) == NOTES_ORDER[:PAGE]
    assert (page["total"], page["offset"]) == (12, 0)
    assert env.log[-1].kind == "read"
    page = user(env, "list_notes", offset=10, limit=5)
    assert ids(page["notes"]) == NOTES_ORDER[10:]
    assert user(env, "list_notes", offset=20)["notes"] == []
    assert screen_of(env) == "List"


@pytest.mark.parametrize("args", [{"limit": 0}, {"limit": 101}, {"offset": -1}])
def test_list_notes_rejects_bad_paging(env: Environment, args: dict) -> None:
    err(env.call("user", "list_notes", args), "offset must be >= 0 and limit between 1 and 100")
    assert screen_of(env) == "List"


def test_search_notes_matches_every_word_in_any_folder(env: Environment) -> None:
    assert ids(user(env, "search_notes", query="quarterly review")) == ["note-review", "note-review-q4"]
    assert ids(user(env, "search_notes", query="REVENUE roadmap")) == ["note-review"]  # content, any case
    assert ids(user(env, "search_notes", query="pasta")) == ["note-pasta-bake", "note-pasta"]
    assert ids(user(env, "search_notes", query="spinach")) == ["note-groceries", "note-curry"]
    assert ids(user(env, "search_notes", query="plumber")) == ["note-untitled"]  # untitled, by content
    assert ids(user(env, "search_notes", query="lena")) == ["note-birthdays", "note-gifts"]
    assert user(env, "search_notes", query="karaoke") == []
    assert user(env, "search_notes", query="Recipes") == []  # the folder's name is not searched
    err(env.call("user", "search_notes", {"query": "  "}), "empty")
    assert screen_of(env) == "List"
    assert env.log[-2].kind == "read"


def test_open_note_goes_to_detail(env: Environment) -> None:
    shown = user(env, "open_note", note_id="note-wifi")
    assert shown["content"] == "Home network Maple-5G, password tulip-river-42"
    assert screen_of(env) == "Detail"
    assert stack(env) == ["List(folder='Notes')", "Detail(note_id='note-wifi')"]


def test_open_note_of_another_folder(env: Environment) -> None:
    user(env, "search_notes", query="lisbon")
    assert user(env, "open_note", note_id="note-lisbon")["folder"] == "Personal"
    assert screen_of(env) == "Detail"


def test_open_unknown_note_is_an_error_and_stays(env: Environment) -> None:
    err(env.call("user", "open_note", {"note_id": "note-nope"}), "no note with id 'note-nope'")
    assert screen_of(env) == "List"


def test_new_note_opens_an_empty_draft_in_this_folder(env: Environment) -> None:
    before = env.snapshot()
    draft = user(env, "new_note")
    assert draft == {"note_id": None, "folder": "Notes", "title": "", "content": "", "attachments": []}
    assert screen_of(env) == "Edit"
    assert stack(env)[0] == "List(folder='Notes')"
    assert env.snapshot() == before


def test_list_folders_goes_to_folders_with_counts(env: Environment) -> None:
    shown = user(env, "list_folders")
    assert shown == [
        {"name": "Notes", "note_count": 12},
        {"name": "Personal", "note_count": 3},
        {"name": "Work", "note_count": 4},
        {"name": "Recipes", "note_count": 3},
        {"name": "Archive", "note_count": 0},
    ]
    assert screen_of(env) == "Folders"
    assert stack(env) == ["List(folder='Notes')", "Folders()"]


# -- Folders -----------------------------------------------------------------------------------------


def test_folders_listing_follows_changes(env: Environment) -> None:
    user(env, "list_folders")
    agent(env, "new_folder", name="Ideas")
    shown = user(env, "list_folders")
    assert shown[-1] == {"name": "Ideas", "note_count": 0}
    assert env.log[-1].kind == "read"
    assert screen_of(env) == "Folders"


def test_open_folder_replaces_the_list(env: Environment) -> None:
    user(env, "list_folders")
    page = user(env, "open_folder", folder="work")  # any case
    assert page["folder"] == "Work"
    assert ids(page["notes"]) == ["note-standup", "note-review", "note-george", "note-review-q4"]
    assert page["total"] == 4
    assert screen_of(env) == "List"
    assert stack(env) == ["List(folder='Work')"]
    assert ids(user(env, "list_notes", limit=2)["notes"]) == ["note-standup", "note-review"]
    # an empty folder
    user(env, "list_folders")
    assert user(env, "open_folder", folder="Archive") == {
        "folder": "Archive",
        "notes": [],
        "total": 0,
        "offset": 0,
        "showing": "all 0",
    }
    assert stack(env) == ["List(folder='Archive')"]


def test_open_unknown_folder_is_an_error_and_stays(env: Environment) -> None:
    user(env, "list_folders")
    err(
        env.call("user", "open_folder", {"folder": "Music"}),
        "no folder named 'music'",
        "notes, personal, work, recipes, archive",
    )
    assert screen_of(env) == "Folders"
    assert stack(env) == ["List(folder='Notes')", "Folders()"]


def test_new_note_from_another_folder(env: Environment) -> None:
    user(env, "list_folders")
    user(env, "open_folder", folder="Recipes")
    assert user(env, "new_note")["folder"] == "Recipes"
    user(env, "set_title", title="Shakshuka")
    saved = user(env, "save")
    assert saved["folder"] == "Recipes"
    assert notes(env)[saved["note_id"]]["folder"] == "Recipes"


# -- Detail ------------------------------------------------------------------------------------------


def test_detail_refresh_and_list_attachments(env: Environment) -> None:
    user(env, "list_folders")
    user(env, "open_folder", folder="Personal")
    user(env, "open_note", note_id="note-apartment")
    assert user(env, "list_attachments") == [PLAN, LEASE]
    assert env.log[-1].kind == "read"
    assert user(env, "refresh")["title"] == "Apartment viewing checklist"
    agent(env, "update_note", note_id="note-apartment", content="Ask about the boiler and parking")
    assert user(env, "refresh")["content"] == "Ask about the boiler and parking"
    assert screen_of(env) == "Detail"


def test_add_attachment_stays_and_updates_the_note(env: Environment) -> None:
    user(env, "open_note", note_id="note-todo")
    env.advance(timedelta(hours=1))
    shown = user(env, "add_attachment", path="Documents/budget.xlsx")  # normalised
    assert shown["attachments"] == [BUDGET]
    assert env.log[-1].kind == "write"
    assert screen_of(env) == "Detail"
    stored = notes(env)["note-todo"]
    assert stored["attachments"] == [BUDGET]
    assert stored["updated_at"] == LATER
    assert user(env, "list_attachments") == [BUDGET]
    # the note is now the most recently updated one after the pinned note
    assert ids(agent(env, "list_notes", limit=2)["notes"]) == ["note-groceries", "note-todo"]


def test_remove_attachment_stays_and_keeps_the_file(env: Environment) -> None:
    user(env, "open_note", note_id="note-apartment")
    shown = user(env, "remove_attachment", path=PLAN)
    assert shown["attachments"] == [LEASE]
    assert notes(env)["note-apartment"]["attachments"] == [LEASE]
    assert PLAN in env.snapshot()["files"]["files"]
    assert env.log[-1].kind == "write"
    assert screen_of(env) == "Detail"


@pytest.mark.parametrize(
    ("action", "args", "messages"),
    [
        ("add_attachment", {"path": PLAN}, [f"{PLAN} is already attached to note 'note-apartment'"]),
        ("add_attachment", {"path": "/Documents/deed.pdf"}, ["no file at /documents/deed.pdf"]),
        ("add_attachment", {"path": "../secrets"}, ["leaves the phone's file storage"]),
        ("remove_attachment", {"path": BUDGET}, ["is not attached", f"attachments: {PLAN}, {LEASE}"]),
        ("remove_attachment", {"path": ""}, ["path is empty"]),
        ("move", {"folder": "Personal"}, ["already in personal"]),
        ("move", {"folder": "Music"}, ["no folder named 'music'"]),
    ],
)
def test_detail_errors_change_nothing(env: Environment, action: str, args: dict, messages: list[str]) -> None:
    user(env, "open_note", note_id="note-apartment")
    before = env.snapshot()
    err(env.call("user", action, args), *messages)
    assert env.snapshot() == before
    assert screen_of(env) == "Detail"


def test_delete_returns_to_the_list(env: Environment) -> None:
    user(env, "list_folders")
    user(env, "open_folder", folder="Work")
    user(env, "open_note", note_id="note-review-q4")
    assert "note-review-q4" in user(env, "delete")
    assert screen_of(env) == "List"
    assert stack(env) == ["List(folder='Work')"]
    assert "note-review-q4" not in notes(env)
    assert env.log[-1].kind == "write"
    assert ids(user(env, "list_notes")["notes"]) == ["note-standup", "note-review", "note-george"]
    assert WHITEBOARD in env.snapshot()["files"]["files"]


def test_edit_opens_a_prefilled_draft(env: Environment) -> None:
    user(env, "open_note", note_id="note-apartment")
    draft = user(env, "edit")
    assert draft == {
        "note_id": "note-apartment",
        "folder": "Personal",
        "title": "Apartment viewing checklist",
        "content": "Ask about the boiler, pets and the lease term",
        "attachments": [PLAN, LEASE],
    }
    assert [s.screen_name() for s in env.system.stacks["notes"]] == ["List", "Detail", "Edit"]


def test_duplicate_opens_the_copy(env: Environment) -> None:
    user(env, "open_note", note_id="note-apartment")
    env.advance(timedelta(hours=1))
    copy = user(env, "duplicate")
    copy_id = copy["note_id"]
    assert copy_id != "note-apartment"
    assert copy["title"] == "Apartment viewing checklist (copy)"
    assert screen_of(env) == "Detail"
    assert stack(env) == ["List(folder='Notes')", f"Detail(note_id='{copy_id}')"]
    assert env.log[-1].kind == "write"
    stored = notes(env)[copy_id]
    original = notes(env)["note-apartment"]
    assert stored == {
        **original,
        "note_id": copy_id,
        "title": "Apartment viewing checklist (copy)",
        "created_at": LATER,
        "updated_at": LATER,
    }
    assert original["updated_at"] == "2025-03-01T19:00:00Z"  # untouched
    # the copy has its own attachment list
    user(env, "remove_attachment", path=LEASE)
    assert notes(env)["note-apartment"]["attachments"] == [PLAN, LEASE]


def test_duplicate_of_a_pinned_note_is_not_pinned(env: Environment) -> None:
    user(env, "open_note", note_id="note-groceries")
    copy = user(env, "duplicate")
    assert copy["pinned"] is False
    ok(env.call("user", "go_back"))
    assert ids(user(env, "list_notes", limit=2)["notes"]) == ["note-groceries", copy["note_id"]]


def test_move_lands_on_the_target_folder(env: Environment) -> None:
    user(env, "open_note", note_id="note-gym")
    moved = user(env, "move", folder="personal")
    assert moved["folder"] == "Personal"
    assert screen_of(env) == "List"
    assert stack(env) == ["List(folder='Personal')"]
    assert env.log[-1].kind == "write"
    assert notes(env)["note-gym"]["folder"] == "Personal"
    assert notes(env)["note-gym"]["updated_at"] == "2025-02-15T07:30:00Z"  # moving is not editing
    assert ids(user(env, "list_notes")["notes"]) == [
        "note-apartment",
        "note-lisbon",
        "note-gifts",
        "note-gym",
    ]


def test_detail_of_a_note_deleted_meanwhile(env: Environment) -> None:
    user(env, "open_note", note_id="note-bike")
    agent(env, "delete_note", note_id="note-bike")
    before = env.snapshot()
    for action, args in [
        ("refresh", {}),
        ("list_attachments", {}),
        ("add_attachment", {"path": PLAN}),
        ("remove_attachment", {"path": PLAN}),
        ("delete", {}),
        ("edit", {}),
        ("duplicate", {}),
        ("move", {"folder": "Work"}),
    ]:
        err(env.call("user", action, args), "no note with id 'note-bike'")
        assert screen_of(env) == "Detail"
    assert env.snapshot() == before


# -- Edit --------------------------------------------------------------------------------------------


def test_create_flow_from_the_list(env: Environment) -> None:
    before = set(notes(env))
    user(env, "new_note")
    env.advance(timedelta(hours=1))
    assert user(env, "set_title", title="  Hardware store  ")["title"] == "Hardware store"
    assert user(env, "set_content", content="Wall plugs\nSandpaper\n")["content"] == "Wall plugs\nSandpaper\n"
    draft = user(env, "attach_file", path="Photos/whiteboard.jpg")
    assert draft["attachments"] == [WHITEBOARD]
    draft = user(env, "attach_file", path=BUDGET)
    assert draft["attachments"] == [WHITEBOARD, BUDGET]
    assert set(notes(env)) == before  # nothing is stored before saving
    assert env.log[-1].kind == "ui"

    saved = user(env, "save")
    assert env.log[-1].kind == "write"
    new_id = saved["note_id"]
    assert set(notes(env)) == before | {new_id}
    assert notes(env)[new_id] == {
        "note_id": new_id,
        "title": "Hardware store",
        "content": "Wall plugs\nSandpaper\n",
        "folder": "Notes",
        "attachments": [WHITEBOARD, BUDGET],
        "created_at": LATER,
        "updated_at": LATER,
        "pinned": False,
    }
    assert screen_of(env) == "Detail"
    assert stack(env) == ["List(folder='Notes')", f"Detail(note_id='{new_id}')"]
    ok(env.call("user", "go_back"))
    assert ids(user(env, "list_notes", limit=2)["notes"]) == ["note-groceries", new_id]


def test_a_note_may_have_only_content_or_only_a_title(env: Environment) -> None:
    user(env, "new_note")
    user(env, "set_content", content="Door code 2580")
    only_content = user(env, "save")
    assert (only_content["title"], only_content["content"]) == ("", "Door code 2580")
    ok(env.call("user", "go_back"))
    user(env, "new_note")
    user(env, "set_title", title="Call Mum")
    only_title = user(env, "save")
    assert (only_title["title"], only_title["content"]) == ("Call Mum", "")


def test_saving_an_empty_note_is_an_error(env: Environment) -> None:
    user(env, "new_note")
    user(env, "set_title", title="   ")
    user(env, "set_content", content=" \n ")
    user(env, "attach_file", path=PLAN)
    before = env.snapshot()
    err(env.call("user", "save"), "needs a title or some content")
    assert env.snapshot() == before
    assert screen_of(env) == "Edit"


@pytest.mark.parametrize(
    ("path", "message"),
    [(PLAN, "already attached"), ("/Documents/deed.pdf", "no file at /documents/deed.pdf"), ("", "empty")],
)
def test_attach_file_errors_keep_the_draft(env: Environment, path: str, message: str) -> None:
    user(env, "new_note")
    user(env, "set_title", title="Draft")
    user(env, "attach_file", path=PLAN)
    before = env.snapshot()
    err(env.call("user", "attach_file", {"path": path}), message)
    assert env.snapshot() == before
    assert user(env, "set_content", content="x")["attachments"] == [PLAN]
    assert screen_of(env) == "Edit"


def test_saving_a_new_note_whose_file_went_away_is_an_error(env: Environment) -> None:
    user(env, "new_note")
    user(env, "set_title", title="Budget talk")
    user(env, "attach_file", path=PLAN)
    user(env, "attach_file", path=BUDGET)
    del env.app("files").state.files[BUDGET]
    before = env.snapshot()
    err(env.call("user", "save"), f"no file at {BUDGET}")
    assert env.snapshot() == before  # not even the note without the file
    assert screen_of(env) == "Edit"


def test_saving_a_new_note_in_a_folder_deleted_meanwhile_is_an_error(env: Environment) -> None:
    user(env, "list_folders")
    user(env, "open_folder", folder="Archive")
    user(env, "new_note")
    user(env, "set_title", title="Old tax papers")
    agent(env, "delete_folder", name="Archive")
    before = env.snapshot()
    err(env.call("user", "save"), "no folder named 'archive'")
    assert env.snapshot() == before
    assert screen_of(env) == "Edit"


def test_edit_flow_saves_back_to_the_detail(env: Environment) -> None:
    user(env, "open_note", note_id="note-todo")
    user(env, "edit")
    env.advance(timedelta(hours=1))
    user(env, "set_title", title="To do this week (urgent)")
    user(env, "set_content", content="Renew passport\nPay rent by the 5th\nBook dentist\nCall Ivan")
    user(env, "attach_file", path=PASSPORT)
    saved = user(env, "save")
    assert env.log[-1].kind == "write"
    assert saved["title"] == "To do this week (urgent)"
    assert saved["attachments"] == [PASSPORT]
    stored = notes(env)["note-todo"]
    assert stored == {
        **note("note-todo", "To do this week (urgent)", saved["content"], "Notes", "03-01 09:00"),
        "updated_at": LATER,
        "attachments": [PASSPORT],
        "pinned": False,
    }
    assert screen_of(env) == "Detail"
    assert stack(env) == ["List(folder='Notes')", "Detail(note_id='note-todo')"]
    assert user(env, "refresh") == saved


def test_edit_only_adding_a_file(env: Environment) -> None:
    user(env, "open_note", note_id="note-apartment")
    user(env, "edit")
    user(env, "attach_file", path=BUDGET)
    user(env, "save")
    stored = notes(env)["note-apartment"]
    assert stored["attachments"] == [PLAN, LEASE, BUDGET]
    assert stored["title"] == "Apartment viewing checklist"
    assert stored["updated_at"] == NOW


def test_saving_an_unchanged_note_writes_nothing(env: Environment) -> None:
    user(env, "open_note", note_id="note-wifi")
    user(env, "edit")
    user(env, "set_title", title="Wi-Fi password")
    before = env.snapshot()
    writes = env.apps["notes"].write_count
    user(env, "save")
    assert env.snapshot() == before
    assert env.apps["notes"].write_count == writes
    assert env.log[-1].kind == "ui"
    assert screen_of(env) == "Detail"


def test_saving_an_edit_of_a_note_deleted_meanwhile_is_an_error(env: Environment) -> None:
    user(env, "open_note", note_id="note-quotes")
    user(env, "edit")
    user(env, "set_title", title="Favourite quotes")
    agent(env, "delete_note", note_id="note-quotes")
    before = env.snapshot()
    err(env.call("user", "save"), "no note with id 'note-quotes'")
    assert env.snapshot() == before
    assert screen_of(env) == "Edit"


def test_discard_a_new_note_changes_nothing(env: Environment) -> None:
    before = env.snapshot()
    user(env, "new_note")
    user(env, "set_title", title="Never saved")
    user(env, "attach_file", path=PLAN)
    assert user(env, "discard") == "Draft discarded."
    assert screen_of(env) == "List"
    assert stack(env) == ["List(folder='Notes')"]
    assert env.snapshot() == before


def test_discard_an_edit_changes_nothing(env: Environment) -> None:
    before = env.snapshot()
    user(env, "open_note", note_id="note-movies")
    user(env, "edit")
    user(env, "set_content", content="")
    user(env, "discard")
    assert screen_of(env) == "Detail"
    assert user(env, "refresh")["content"] == "Past Lives; Perfect Days; Dune part two"
    assert env.snapshot() == before


def test_unknown_argument_is_rejected_and_the_draft_kept(env: Environment) -> None:
    user(env, "new_note")
    user(env, "set_title", title="Draft")
    err(env.call("user", "set_title", {"title": "x", "colour": "red"}), "unexpected argument 'colour'")
    assert user(env, "set_content", content="y")["title"] == "Draft"


# -- agent API ---------------------------------------------------------------------------------------


def test_agent_reads(env: Environment) -> None:
    assert agent(env, "get_note_by_id", note_id="note-lisbon")["attachments"] == [PASSPORT]
    page = agent(env, "list_notes")
    assert ids(page["notes"]) == NOTES_ORDER[:PAGE] and page["total"] == 12
    page = agent(env, "list_notes", folder="RECIPES", offset=1, limit=1)
    assert (page["folder"], ids(page["notes"]), page["total"], page["offset"]) == (
        "Recipes",
        ["note-pasta-bake"],
        3,
        1,
    )
    assert ids(agent(env, "search_notes", query="passport")) == ["note-todo"]
    assert ids(agent(env, "search_notes", query="TP 238")) == ["note-lisbon"]
    assert agent(env, "list_folders")[2] == {"name": "Work", "note_count": 4}
    assert agent(env, "list_attachments", note_id="note-apartment") == [PLAN, LEASE]
    assert agent(env, "list_attachments", note_id="note-wifi") == []


def test_notes_updated_at_the_same_time_list_newest_created_first() -> None:
    seed = [
        note("b", "B", "", "Notes", "02-01 10:00", "03-01 10:00"),
        note("a", "A", "", "Notes", "02-01 10:00", "03-01 10:00"),
        note("c", "C", "", "Notes", "02-02 10:00", "03-01 10:00"),
    ]
    env = make_env(["notes"], {"notes": {"notes": {n["note_id"]: n for n in seed}}})
    assert ids(agent(env, "list_notes")["notes"]) == ["c", "a", "b"]


def test_agent_reads_are_available_in_observe_mode(env: Environment) -> None:
    assert ids(ok(env.call("assistant", "notes__search_notes", {"query": "wifi"}, mode="observe"))) == []
    assert ids(ok(env.call("assistant", "notes__search_notes", {"query": "wi-fi"}, mode="observe"))) == [
        "note-wifi"
    ]
    err(env.call("assistant", "notes__delete_note", {"note_id": "note-wifi"}, mode="observe"), "execute mode")
    assert "note-wifi" in notes(env)


def test_create_note(env: Environment) -> None:
    env.advance(timedelta(hours=1))
    new_id = agent(env, "create_note", title=" Dentist questions ", content="Ask about the crown")["id"]
    assert notes(env)[new_id] == {
        "note_id": new_id,
        "title": "Dentist questions",
        "content": "Ask about the crown",
        "folder": "Notes",
        "attachments": [],
        "created_at": LATER,
        "updated_at": LATER,
        "pinned": False,
    }
    other = agent(env, "create_note", title="Sprint retro", folder="work")["id"]
    assert notes(env)[other]["folder"] == "Work"
    assert notes(env)[other]["content"] == ""
    untitled = agent(env, "create_note", title="", content="Door code 2580", folder="Personal")["id"]
    assert notes(env)[untitled]["title"] == ""
    assert len({new_id, other, untitled}) == 3


def test_new_ids_are_never_reused(env: Environment) -> None:
    first = agent(env, "create_note", title="A")["id"]
    agent(env, "delete_note", note_id=first)
    second = agent(env, "create_note", title="B")["id"]
    third = agent(env, "duplicate_note", note_id=second)["id"]
    assert len({first, second, third}) == 3
    assert first not in notes(env)


def test_update_note(env: Environment) -> None:
    env.advance(timedelta(hours=1))
    updated = agent(env, "update_note", note_id="note-groceries", content="Milk\nEggs\nSpinach\nBread")
    assert updated["content"] == "Milk\nEggs\nSpinach\nBread"
    assert updated["title"] == "Groceries"
    assert updated["updated_at"] == LATER
    assert notes(env)["note-groceries"] == updated
    assert agent(env, "update_note", note_id="note-groceries", title="  Shopping ")["title"] == "Shopping"
    # a title may go if content stays, and the reverse
    assert agent(env, "update_note", note_id="note-wifi", title="")["title"] == ""
    assert agent(env, "update_note", note_id="note-bike", content="")["content"] == ""


def test_update_note_with_the_same_text_keeps_the_time(env: Environment) -> None:
    env.advance(timedelta(hours=1))
    before = env.snapshot()
    agent(env, "update_note", note_id="note-bike", title="Bike lock", content="Code 4-7-1-9")
    assert env.snapshot() == before


def test_delete_note(env: Environment) -> None:
    assert agent(env, "delete_note", note_id="note-untitled") == "Deleted note note-untitled (untitled)."
    assert "Bike lock" in agent(env, "delete_note", note_id="note-bike")
    assert "note-bike" not in notes(env) and "note-untitled" not in notes(env)
    assert agent(env, "list_notes")["total"] == 10


def test_move_note(env: Environment) -> None:
    moved = agent(env, "move_note", note_id="note-wifi", folder="PERSONAL")
    assert moved["folder"] == "Personal"
    assert moved["updated_at"] == "2025-01-05T12:00:00Z"
    assert notes(env)["note-wifi"]["folder"] == "Personal"
    assert agent(env, "list_notes")["total"] == 11
    assert "note-wifi" in ids(agent(env, "list_notes", folder="Personal")["notes"])


def test_duplicate_note(env: Environment) -> None:
    copy_id = agent(env, "duplicate_note", note_id="note-review")["id"]
    copy = notes(env)[copy_id]
    assert copy["title"] == "Quarterly review prep (copy)"
    assert (copy["folder"], copy["content"], copy["attachments"]) == (
        "Work",
        notes(env)["note-review"]["content"],
        [WHITEBOARD],
    )
    assert (copy["created_at"], copy["updated_at"]) == (NOW, NOW)
    untitled_copy = agent(env, "duplicate_note", note_id="note-untitled")["id"]
    assert notes(env)[untitled_copy]["title"] == "(copy)"


def test_folder_management(env: Environment) -> None:
    assert agent(env, "new_folder", name="  Ideas ") == {
        "done": "Created the empty folder 'Ideas'.",
        "id": "Ideas",
    }
    assert folders(env) == [*FOLDERS, "Ideas"]
    result = agent(env, "rename_folder", name="recipes", new_name="Cooking")
    assert result == "Renamed folder 'Recipes' to 'Cooking' (3 notes)."
    assert folders(env) == ["Notes", "Personal", "Work", "Cooking", "Archive", "Ideas"]  # keeps its place
    assert {n["folder"] for n in notes(env).values() if n["note_id"].startswith("note-pasta")} == {"Cooking"}
    assert agent(env, "list_notes", folder="cooking")["total"] == 3
    err(env.call("assistant", "notes__list_notes", {"folder": "Recipes"}, mode="execute"), "no folder")
    # changing only the case of a name is a rename
    assert (
        agent(env, "rename_folder", name="ideas", new_name="IDEAS")
        == "Renamed folder 'Ideas' to 'IDEAS' (0 notes)."
    )
    assert agent(env, "delete_folder", name="ideas") == "Deleted folder 'IDEAS'."
    assert agent(env, "delete_folder", name="Archive") == "Deleted folder 'Archive'."
    assert folders(env) == ["Notes", "Personal", "Work", "Cooking"]
    agent(env, "move_note", note_id="note-gifts", folder="Notes")
    assert (
        agent(env, "rename_folder", name="Personal", new_name="Home")
        == "Renamed folder 'Personal' to 'Home' (2 notes)."
    )
    agent(env, "move_note", note_id="note-apartment", folder="Notes")
    assert (
        agent(env, "rename_folder", name="Home", new_name="Private")
        == "Renamed folder 'Home' to 'Private' (1 note)."
    )


def test_attachments_through_the_api(env: Environment) -> None:
    env.advance(timedelta(hours=1))
    shown = agent(
        env, "add_attachment_to_note", note_id="note-lisbon", path="/Documents/../Documents/lease.pdf"
    )
    assert shown["attachments"] == [PASSPORT, LEASE]
    assert shown["updated_at"] == LATER
    shown = agent(env, "remove_attachment", note_id="note-lisbon", path="Documents/passport_scan.pdf")
    assert shown["attachments"] == [LEASE]
    assert agent(env, "list_attachments", note_id="note-lisbon") == [LEASE]
    # an attachment whose file was deleted from Files can still be removed
    del env.app("files").state.files[LEASE]
    assert agent(env, "remove_attachment", note_id="note-lisbon", path=LEASE)["attachments"] == []


@pytest.mark.parametrize(
    ("tool", "args", "messages"),
    [
        ("get_note_by_id", {"note_id": "ghost"}, "no note with id 'ghost'"),
        ("list_notes", {"folder": "Music"}, "no folder named 'music'. folders: notes, personal"),
        ("list_notes", {"limit": 0}, "limit between 1 and 100"),
        ("list_notes", {"offset": -1}, "offset must be >= 0"),
        ("search_notes", {"query": " "}, "empty"),
        ("list_attachments", {"note_id": "ghost"}, "ghost"),
        ("create_note", {"title": " ", "content": " "}, "needs a title or some content"),
        ("create_note", {"title": "x", "folder": "Music"}, "no folder named 'music'"),
        ("create_note", {"content": "x"}, "missing required argument 'title'"),
        ("update_note", {"note_id": "ghost", "title": "x"}, "ghost"),
        ("update_note", {"note_id": "note-wifi"}, "nothing to change"),
        ("update_note", {"note_id": "note-untitled", "content": ""}, "needs a title or some content"),
        (
            "update_note",
            {"note_id": "note-wifi", "title": "", "content": "  "},
            "needs a title or some content",
        ),
        ("update_note", {"note_id": "note-wifi", "folder": "Work"}, "unexpected argument 'folder'"),
        ("delete_note", {"note_id": "ghost"}, "ghost"),
        ("move_note", {"note_id": "ghost", "folder": "Work"}, "ghost"),
        ("move_note", {"note_id": "note-wifi", "folder": "Music"}, "no folder named 'music'"),
        ("move_note", {"note_id": "note-wifi", "folder": "notes"}, "already in notes"),
        ("duplicate_note", {"note_id": "ghost"}, "ghost"),
        ("new_folder", {"name": "  "}, "needs a name"),
        ("new_folder", {"name": "work"}, "a folder named 'work' already exists"),
        ("rename_folder", {"name": "Music", "new_name": "Songs"}, "no folder named 'music'"),
        ("rename_folder", {"name": "Notes", "new_name": "Inbox"}, "default folder 'notes' cannot be renamed"),
        ("rename_folder", {"name": "Work", "new_name": "personal"}, "'personal' already exists"),
        ("rename_folder", {"name": "Work", "new_name": " "}, "needs a name"),
        ("rename_folder", {"name": "work", "new_name": "Work"}, "already called 'work'"),
        ("delete_folder", {"name": "Music"}, "no folder named 'music'"),
        ("delete_folder", {"name": "notes"}, "default folder 'notes' cannot be deleted"),
        ("delete_folder", {"name": "Work"}, ("still holds 4 notes", "move_note", "delete_note")),
        ("add_attachment_to_note", {"note_id": "ghost", "path": PLAN}, "ghost"),
        ("add_attachment_to_note", {"note_id": "note-wifi", "path": "/nope.txt"}, "no file at /nope.txt"),
        ("add_attachment_to_note", {"note_id": "note-lisbon", "path": PASSPORT}, "already attached"),
        ("add_attachment_to_note", {"note_id": "note-lisbon", "path": "/../etc"}, "leaves"),
        ("remove_attachment", {"note_id": "ghost", "path": PLAN}, "ghost"),
        ("remove_attachment", {"note_id": "note-wifi", "path": PLAN}, ("not attached", "attachments: none")),
    ],
)
def test_agent_api_errors_change_nothing(
    env: Environment, tool: str, args: dict, messages: str | tuple
) -> None:
    before = env.snapshot()
    fragments = (messages,) if isinstance(messages, str) else messages
    err(env.call("assistant", f"notes__{tool}", args, mode="execute"), *fragments)
    assert env.snapshot() == before


def test_delete_folder_with_one_note_says_so(env: Environment) -> None:
    agent(env, "move_note", note_id="note-wifi", folder="Archive")
    err(env.call("assistant", "notes__delete_folder", {"name": "Archive"}, mode="execute"), "holds 1 note;")


def test_the_assistant_cannot_edit_as_someone_else(env: Environment) -> None:
    before = env.snapshot()
    err(
        env.call(
            "assistant",
            "notes__update_shared_note",
            {"note_id": "note-groceries", "content": "x", "editor": "Carol"},
            mode="execute",
        )
    )
    assert env.snapshot() == before


# -- the world ---------------------------------------------------------------------------------------

NEW_LIST = (
    "Milk\nEggs\nSpinach\nOat milk for Carol\nBirthday candles\nParmesan\nLemons\nBread\nCoffee beans\nRice"
)


def test_someone_updates_a_shared_note(env: Environment) -> None:
    env.user_view()  # read what came before
    env.assistant_observation()
    env.advance(timedelta(minutes=30))
    args = {"note_id": "note-groceries", "content": NEW_LIST, "editor": " Carol Rivera "}
    shown = ok(env.call("env", "notes__update_shared_note", args))
    assert shown["content"] == NEW_LIST
    stored = notes(env)["note-groceries"]
    assert (stored["content"], stored["updated_at"]) == (NEW_LIST, "2025-03-03T09:30:00Z")

    user_copy = env.user_view().notifications
    assert len(user_copy) == 1
    assert "Notes: Carol Rivera edited a shared note — Groceries: Milk Eggs Spinach" in user_copy[0]
    assert user_copy[0].endswith("…")  # truncated like a phone notification
    assert "Coffee beans" not in user_copy[0] and "note-groceries" not in user_copy[0]

    assistant_copy = env.assistant_observation().notifications
    assert len(assistant_copy) == 1
    assert "Carol Rivera edited a shared note — Groceries" in assistant_copy[0]
    assert "Coffee beans\nRice" in assistant_copy[0]
    assert assistant_copy[0].endswith("(note_id=note-groceries)")
    notification = env.notifications.inboxes["assistant"].items[-1]
    assert (notification.kind, notification.data) == ("note_updated", {"note_id": "note-groceries"})

    # the user sees it at the top of the list and on the note
    assert ids(user(env, "list_notes", limit=1)["notes"]) == ["note-groceries"]
    assert user(env, "open_note", note_id="note-groceries")["content"] == NEW_LIST


def test_shared_edit_of_an_untitled_note(env: Environment) -> None:
    ok(
        env.call(
            "env",
            "notes__update_shared_note",
            {"note_id": "note-untitled", "content": "Done", "editor": "Ivan"},
        )
    )
    assert "Ivan edited a shared note — Untitled note: Done" in env.user_view().notifications[-1]


def test_saving_a_draft_opened_before_a_shared_edit_keeps_the_users_text(env: Environment) -> None:
    user(env, "open_note", note_id="note-groceries")
    user(env, "edit")
    ok(
        env.call(
            "env",
            "notes__update_shared_note",
            {"note_id": "note-groceries", "content": "Rice", "editor": "Carol"},
        )
    )
    # the draft was opened before Carol's edit: saving it writes the draft's text, the last writer wins
    user(env, "set_title", title="Groceries!")
    saved = user(env, "save")
    assert saved["content"] == "Milk\nEggs\nSpinach\nOat milk for Carol"
    assert user(env, "refresh")["title"] == "Groceries!"


@pytest.mark.parametrize(
    ("args", "message"),
    [
        ({"note_id": "ghost", "content": "x", "editor": "Carol"}, "no note with id 'ghost'"),
        ({"note_id": "note-groceries", "content": "x", "editor": "  "}, "editor cannot be empty"),
        ({"note_id": "note-untitled", "content": " ", "editor": "Ivan"}, "needs a title or some content"),
        ({"note_id": "note-groceries", "editor": "Carol"}, "missing required argument 'content'"),
    ],
)
def test_shared_edit_errors_change_nothing(env: Environment, args: dict, message: str) -> None:
    env.user_view()
    env.assistant_observation()
    before = env.snapshot()
    err(env.call("env", "notes__update_shared_note", args), message)
    assert env.snapshot() == before
    assert env.user_view().notifications == []
    assert env.assistant_observation().notifications == []


# -- a careless user ---------------------------------------------------------------------------------


def test_a_random_user_walks_every_screen() -> None:
    env = make_env(["notes"], SEED)
    walker = RandomUser(random.Random(0))
    for _ in range(3000):
        walker.step(env)  # raise_internal_errors: a crash or an undeclared transition fails the test
    screens = {e.app_screen[1] for e in env.log if e.app_screen}
    assert {"List", "Folders", "Detail", "Edit"} <= screens
    assert sum(e.ok for e in env.log) / len(env.log) > 0.5


def test_detail_and_edit_can_browse_files_to_attach(env: Environment) -> None:
    user(env, "open_note", note_id="note-apartment")
    docs = user(env, "browse_files", directory="/Documents")
    assert PLAN in [e["path"] for e in docs] and screen_of(env) == "Detail"
    user(env, "edit")
    assert [e["type"] for e in user(env, "browse_files")] == ["directory"] * len(user(env, "browse_files"))
    assert screen_of(env) == "Edit"


def test_creating_and_copying_notes_say_what_was_made_where(env: Environment) -> None:
    made = agent(env, "create_note", title=" Packing ", folder="work")
    assert made["done"] == f"Created note {made['id']} 'Packing' in folder 'Work'."
    copy = agent(env, "duplicate_note", note_id=made["id"])
    assert copy["done"] == f"Copied note {made['id']} as {copy['id']} 'Packing (copy)' in folder 'Work'."
