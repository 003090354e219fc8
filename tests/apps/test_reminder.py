from __future__ import annotations

import random
from datetime import UTC, datetime, timedelta

import pytest

from pare.apps.reminder import ReminderEdit, Repetition, next_occurrence
from pare.apps.text import PAGE
from pare.env import Environment
from pare.env.random_walk import RandomUser
from pare.errors import UserInputError
from tests.conftest import err, make_env, ok, screen_of


def reminder(reminder_id: str, title: str, due: str, **fields: object) -> dict:
    """A seed reminder; ``due`` is "YYYY-MM-DD HH:MM" in UTC."""
    return {
        "reminder_id": reminder_id,
        "title": title,
        "due_datetime": f"{due.replace(' ', 'T')}:00Z",
        **fields,
    }


RENT_NOTE = (
    "Transfer 1,450 to Bob Okafor (landlord) by bank transfer, reference MARCH-RENT-12B, account ending 4471."
)
# The episode starts on Monday 2025-03-03 at 09:00 UTC. Two reminders are already overdue (and were
# announced before the episode began); the rest lie ahead, some repeating. Distractors look alike: three
# dentist reminders, two about money.
# fmt: off
REMINDERS = [
    reminder("rem-call-mom", "Call Mom back", "2025-03-02 18:00", announced=True),
    reminder("rem-dentist-call", "Call the dentist to reschedule", "2025-03-03 08:30",
             description="Smile Dental: +1 555 0142", announced=True),
    reminder("rem-dentist", "Leave for the dentist", "2025-03-03 13:00",
             description="Appointment at 14:00, Smile Dental, 12 Oak St"),
    reminder("rem-vitamins", "Take vitamins", "2025-03-04 08:00", repetition="daily"),
    reminder("rem-slides", "Finish the quarterly review slides", "2025-03-04 15:00",
             description="Alice needs them before Wednesday's review"),
    reminder("rem-rent", "Pay rent", "2025-03-05 09:00", description=RENT_NOTE, repetition="monthly"),
    reminder("rem-recycling", "Put out the recycling", "2025-03-05 19:00", repetition="weekly"),
    reminder("rem-plants", "Water the neighbours' plants", "2025-03-08 10:00", repetition="weekly",
             repeat_until="2025-03-22T23:59:00Z", description="Ferns twice as much; key under the mat"),
    reminder("rem-dana-bday", "Dana's birthday", "2025-03-14 08:00", repetition="yearly",
             description="Buy the book she mentioned"),
    reminder("rem-tax", "File the tax return", "2025-03-31 09:00"),
    reminder("rem-car-loan", "Car loan payment", "2025-03-31 12:00", repetition="monthly",
             description="Auto-debit, check the balance"),
    reminder("rem-passport", "Renew passport", "2025-04-15 09:00",
             description="Expires in June; book an appointment at the consulate"),
    reminder("rem-dentist-checkup", "Book a dentist check-up", "2025-06-03 09:00"),
]
# fmt: on
SEED = {"reminder": {"reminders": {r["reminder_id"]: r for r in REMINDERS}}}
ALL = [r["reminder_id"] for r in REMINDERS]  # already in due order
DUE = ["rem-call-mom", "rem-dentist-call"]
UPCOMING = ALL[2:]


@pytest.fixture
def env() -> Environment:
    env = make_env(["reminder"], SEED)
    ok(env.call("user", "open_app", {"app_name": "reminder"}))
    return env


def reminders(env: Environment) -> dict:
    return env.snapshot()["reminder"]["reminders"]


def ids(listing: list[dict]) -> list[str]:
    return [r["reminder_id"] for r in listing]


def stack(env: Environment) -> list[str]:
    return [s.screen_name() for s in env.system.stacks["reminder"]]


def agent(env: Environment, tool: str, **args: object) -> object:
    return ok(env.call("assistant", f"reminder__{tool}", args, mode="execute"))


def announced(env: Environment) -> list[tuple[str, str]]:
    """(time, reminder id) of every reminder notification so far, as the assistant received them."""
    return [
        (n.time.strftime("%m-%d %H:%M"), n.data["reminder_id"])
        for n in env.notifications.inboxes["assistant"].items
        if n.kind == "reminder_due"
    ]


def clear_notifications(env: Environment) -> None:
    env.user_view()
    env.assistant_observation()


# -- seed data -------------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("bad", "message"),
    [
        ({"y": reminder("x", "Stray", "2025-03-04 10:00")}, "has reminder_id 'x'"),
        (
            {"x": reminder("x", "Once", "2025-03-04 10:00", repeat_until="2025-03-09T00:00:00Z")},
            "only applies to a repeating reminder",
        ),
        (
            {
                "x": reminder(
                    "x",
                    "Backwards",
                    "2025-03-04 10:00",
                    repetition="daily",
                    repeat_until="2025-03-01T00:00:00Z",
                )
            },
            "must not be before the due time",
        ),
        ({"x": reminder("x", "Often", "2025-03-04 10:00", repetition="hourly")}, "repetition"),
    ],
)
def test_seed_is_validated(bad: dict, message: str) -> None:
    with pytest.raises(UserInputError, match=message):
        make_env(["reminder"], {"reminder": {"reminders": bad}})


def test_seed_repetition_accepts_any_case() -> None:
    env = make_env(
        ["reminder"],
        {"reminder": {"reminders": {"x": reminder("x", "Gym", "2025-03-04 07:00", repetition="Weekly")}}},
    )
    assert reminders(env)["x"]["repetition"] == "weekly"
    assert reminders(env)["x"]["announced"] is False
    assert reminders(env)["x"]["description"] == ""


# -- List ------------------------------------------------------------------------------------------


def test_opens_on_the_list(env: Environment) -> None:
    assert screen_of(env) == "List"


def test_list_all_reminders_sorted_by_due_time(env: Environment) -> None:
    shown = ok(env.call("user", "list_all_reminders"))
    assert ids(shown) == ALL
    assert shown[5]["description"] == RENT_NOTE
    assert screen_of(env) == "List"
    assert env.log[-1].kind == "read"


def test_list_due_reminders_shows_those_due_now_or_before(env: Environment) -> None:
    assert ids(ok(env.call("user", "list_due_reminders"))) == DUE
    assert screen_of(env) == "List"
    assert env.log[-1].kind == "read"
    agent(env, "add_reminder", title="Start the laundry", due_datetime="2025-03-03 09:00")  # exactly now
    assert ids(ok(env.call("user", "list_due_reminders"))) == [*DUE, "reminder-1"]


def test_list_upcoming_reminders(env: Environment) -> None:
    shown = ok(env.call("user", "list_upcoming_reminders"))
    assert ids(shown["reminders"]) == UPCOMING[:PAGE]
    assert shown["total"] == len(UPCOMING) == 11
    assert shown["showing"] == "1-5 of 11; offset=5 shows the next"
    shown = ok(env.call("user", "list_upcoming_reminders", {"offset": 10}))
    assert ids(shown["reminders"]) == UPCOMING[10:]
    shown = ok(env.call("user", "list_upcoming_reminders", {"limit": 3}))
    assert ids(shown["reminders"]) == ["rem-dentist", "rem-vitamins", "rem-slides"]
    assert shown["total"] == 11
    assert screen_of(env) == "List"
    assert env.log[-1].kind == "read"


def test_lists_follow_the_clock(env: Environment) -> None:
    env.advance(timedelta(days=1))  # Tue 09:00: the dentist (13:00) and the vitamins (08:00) fired
    assert ids(ok(env.call("user", "list_due_reminders"))) == [*DUE, "rem-dentist"]
    upcoming = ok(env.call("user", "list_upcoming_reminders", {"limit": 2}))
    assert ids(upcoming["reminders"]) == ["rem-slides", "rem-vitamins"]  # vitamins moved to Wednesday
    assert upcoming["total"] == 10


@pytest.mark.parametrize("limit", [0, 101])
def test_list_upcoming_rejects_a_bad_limit(env: Environment, limit: int) -> None:
    err(env.call("user", "list_upcoming_reminders", {"limit": limit}), "limit between 1 and 100")
    assert screen_of(env) == "List"


def test_open_reminder_goes_to_detail(env: Environment) -> None:
    shown = ok(env.call("user", "open_reminder", {"reminder_id": "rem-rent"}))
    assert shown["title"] == "Pay rent"
    assert shown["repetition"] == "monthly"
    assert screen_of(env) == "Detail"
    assert stack(env) == ["List", "Detail"]
    assert ok(env.call("user", "refresh"))["reminder_id"] == "rem-rent"
    assert env.log[-1].kind == "read"


def test_open_unknown_reminder_is_an_error_and_stays(env: Environment) -> None:
    err(env.call("user", "open_reminder", {"reminder_id": "rem-nope"}), "no reminder with id 'rem-nope'")
    assert screen_of(env) == "List"


# -- Detail ----------------------------------------------------------------------------------------


def test_refresh_shows_changes_made_meanwhile(env: Environment) -> None:
    ok(env.call("user", "open_reminder", {"reminder_id": "rem-slides"}))
    agent(env, "update_reminder", reminder_id="rem-slides", updates={"due_datetime": "2025-03-04 12:00"})
    assert ok(env.call("user", "refresh"))["due_datetime"] == "2025-03-04T12:00:00Z"
    assert screen_of(env) == "Detail"


def test_delete_returns_to_the_list(env: Environment) -> None:
    ok(env.call("user", "open_reminder", {"reminder_id": "rem-tax"}))
    assert "rem-tax" in ok(env.call("user", "delete"))
    assert screen_of(env) == "List"
    assert stack(env) == ["List"]
    assert "rem-tax" not in reminders(env)
    assert env.log[-1].kind == "write"
    assert "rem-tax" not in ids(ok(env.call("user", "list_all_reminders")))


def test_detail_of_a_reminder_deleted_meanwhile(env: Environment) -> None:
    ok(env.call("user", "open_reminder", {"reminder_id": "rem-passport"}))
    agent(env, "delete_reminder", reminder_id="rem-passport")
    before = env.snapshot()
    err(env.call("user", "refresh"), "no reminder with id 'rem-passport'")
    err(env.call("user", "delete"), "no reminder with id 'rem-passport'")
    err(env.call("user", "edit"), "no reminder with id 'rem-passport'")
    assert env.snapshot() == before
    assert screen_of(env) == "Detail"
    ok(env.call("user", "go_back"))
    assert screen_of(env) == "List"


# -- Edit ------------------------------------------------------------------------------------------


def test_create_flow_from_the_list(env: Environment) -> None:
    before = len(reminders(env))
    draft = ok(env.call("user", "create_new"))
    assert screen_of(env) == "Edit"
    assert stack(env) == ["List", "Edit"]
    assert draft == {
        "reminder_id": None,
        "title": None,
        "description": "",
        "due_datetime": "2025-03-03T10:00:00Z",  # the next full hour
        "repetition": "none",
        "repeat_until": None,
    }
    ok(env.call("user", "set_title", {"title": "  Stretch  "}))
    ok(env.call("user", "set_description", {"description": " Ten minutes, back and shoulders "}))
    ok(env.call("user", "set_due_datetime", {"due_datetime": "2025-03-04 17:30"}))
    draft = ok(
        env.call("user", "set_repetition", {"repetition": "Daily", "repeat_until": "2025-03-10 23:00"})
    )
    assert draft == {
        "reminder_id": None,
        "title": "Stretch",
        "description": "Ten minutes, back and shoulders",
        "due_datetime": "2025-03-04T17:30:00Z",
        "repetition": "daily",
        "repeat_until": "2025-03-10T23:00:00Z",
    }
    assert len(reminders(env)) == before  # nothing saved yet
    assert screen_of(env) == "Edit"
    assert env.log[-1].kind == "ui"

    saved = ok(env.call("user", "save"))
    assert env.log[-1].kind == "write"
    assert screen_of(env) == "Detail"
    assert stack(env) == ["List", "Detail"]  # the Edit screen was replaced
    assert saved["reminder_id"] == "reminder-1"
    assert reminders(env)["reminder-1"] == {
        "reminder_id": "reminder-1",
        "title": "Stretch",
        "description": "Ten minutes, back and shoulders",
        "due_datetime": "2025-03-04T17:30:00Z",
        "repetition": "daily",
        "repeat_until": "2025-03-10T23:00:00Z",
        "set_for": "2025-03-04T17:30:00Z",
        "announced": False,
    }
    assert len(reminders(env)) == before + 1
    assert ok(env.call("user", "refresh"))["reminder_id"] == "reminder-1"
    ok(env.call("user", "go_back"))
    assert screen_of(env) == "List"
    assert "reminder-1" in ids(ok(env.call("user", "list_upcoming_reminders", {"limit": 100}))["reminders"])


def test_new_reminder_is_due_at_the_next_full_hour(env: Environment) -> None:
    env.advance(timedelta(minutes=20))
    assert ok(env.call("user", "create_new"))["due_datetime"] == "2025-03-03T10:00:00Z"
    ok(env.call("user", "cancel"))
    env.advance(timedelta(minutes=40))  # 10:00 sharp
    assert ok(env.call("user", "create_new"))["due_datetime"] == "2025-03-03T11:00:00Z"


def test_save_without_a_title_is_an_error_and_stays(env: Environment) -> None:
    ok(env.call("user", "create_new"))
    before = env.snapshot()
    err(env.call("user", "save"), "no title", "set_title")
    assert env.snapshot() == before
    assert screen_of(env) == "Edit"
    err(env.call("user", "set_title", {"title": "   "}), "cannot be empty")
    assert ok(env.call("user", "set_description", {"description": "x"}))["title"] is None
    assert screen_of(env) == "Edit"


def test_set_repetition_errors_keep_the_draft(env: Environment) -> None:
    ok(env.call("user", "create_new"))
    ok(env.call("user", "set_repetition", {"repetition": "weekly", "repeat_until": "2025-03-31 00:00"}))
    err(
        env.call("user", "set_repetition", {"repetition": "none", "repeat_until": "2025-03-31 00:00"}),
        "only applies to a repeating reminder",
    )
    err(
        env.call("user", "set_repetition", {"repetition": "daily", "repeat_until": "2025-03-03 09:30"}),
        "must not be before the due time (2025-03-03 10:00)",
    )
    err(env.call("user", "set_repetition", {"repetition": "fortnightly"}), "repetition")
    screen = env.system.current_screen()
    assert isinstance(screen, ReminderEdit)
    assert (screen.repetition, screen.repeat_until) == (Repetition.WEEKLY, datetime(2025, 3, 31, tzinfo=UTC))
    assert screen_of(env) == "Edit"
    draft = ok(env.call("user", "set_repetition", {"repetition": "NONE"}))  # clears the end too
    assert (draft["repetition"], draft["repeat_until"]) == ("none", None)


def test_save_rejects_a_due_time_after_the_end_of_the_repetition(env: Environment) -> None:
    ok(env.call("user", "create_new"))
    ok(env.call("user", "set_title", {"title": "Physio exercises"}))
    ok(env.call("user", "set_repetition", {"repetition": "daily", "repeat_until": "2025-03-07 23:00"}))
    ok(env.call("user", "set_due_datetime", {"due_datetime": "2025-03-09 08:00"}))
    before = env.snapshot()
    err(env.call("user", "save"), "must not be before the due time")
    assert env.snapshot() == before
    assert screen_of(env) == "Edit"


def test_time_zones_are_converted_to_utc(env: Environment) -> None:
    ok(env.call("user", "create_new"))
    ok(env.call("user", "set_title", {"title": "Call the Lisbon office"}))
    draft = ok(env.call("user", "set_due_datetime", {"due_datetime": "2025-03-04T10:00:00+01:00"}))
    assert draft["due_datetime"] == "2025-03-04T09:00:00Z"
    saved = ok(env.call("user", "save"))
    assert reminders(env)[saved["reminder_id"]]["due_datetime"] == "2025-03-04T09:00:00Z"


def test_edit_flow_from_detail(env: Environment) -> None:
    ok(env.call("user", "open_reminder", {"reminder_id": "rem-plants"}))
    draft = ok(env.call("user", "edit"))
    assert screen_of(env) == "Edit"
    assert stack(env) == ["List", "Detail", "Edit"]
    assert draft == {
        "reminder_id": "rem-plants",
        "title": "Water the neighbours' plants",
        "description": "Ferns twice as much; key under the mat",
        "due_datetime": "2025-03-08T10:00:00Z",
        "repetition": "weekly",
        "repeat_until": "2025-03-22T23:59:00Z",
    }
    ok(env.call("user", "set_title", {"title": "Water the plants"}))
    ok(env.call("user", "set_due_datetime", {"due_datetime": "2025-03-07 18:00"}))
    ok(env.call("user", "set_repetition", {"repetition": "daily", "repeat_until": "2025-03-12 20:00"}))
    saved = ok(env.call("user", "save"))
    assert env.log[-1].kind == "write"
    assert saved["title"] == "Water the plants"
    assert screen_of(env) == "Detail"
    assert stack(env) == ["List", "Detail"]
    assert ok(env.call("user", "refresh"))["reminder_id"] == "rem-plants"
    assert reminders(env)["rem-plants"] == {
        "reminder_id": "rem-plants",
        "title": "Water the plants",
        "description": "Ferns twice as much; key under the mat",  # untouched fields are kept
        "due_datetime": "2025-03-07T18:00:00Z",
        "repetition": "daily",
        "repeat_until": "2025-03-12T20:00:00Z",
        "set_for": "2025-03-07T18:00:00Z",
        "announced": False,
    }
    ok(env.call("user", "go_back"))
    assert screen_of(env) == "List"


def test_saving_an_unchanged_reminder_writes_nothing(env: Environment) -> None:
    ok(env.call("user", "open_reminder", {"reminder_id": "rem-rent"}))
    ok(env.call("user", "edit"))
    ok(env.call("user", "set_title", {"title": " Pay rent "}))  # the same once stripped
    before = env.snapshot()
    writes = env.apps["reminder"].write_count
    ok(env.call("user", "save"))
    assert env.snapshot() == before
    assert env.apps["reminder"].write_count == writes
    assert env.log[-1].kind == "ui"
    assert screen_of(env) == "Detail"


def test_saving_an_edit_of_a_reminder_deleted_meanwhile_is_an_error(env: Environment) -> None:
    ok(env.call("user", "open_reminder", {"reminder_id": "rem-slides"}))
    ok(env.call("user", "edit"))
    ok(env.call("user", "set_title", {"title": "Finish the slides"}))
    agent(env, "delete_reminder", reminder_id="rem-slides")
    before = env.snapshot()
    err(env.call("user", "save"), "no reminder with id 'rem-slides'")
    assert env.snapshot() == before
    assert screen_of(env) == "Edit"


def test_cancel_a_new_reminder_returns_to_the_list(env: Environment) -> None:
    before = env.snapshot()
    ok(env.call("user", "create_new"))
    ok(env.call("user", "set_title", {"title": "Never saved"}))
    ok(env.call("user", "cancel"))
    assert screen_of(env) == "List"
    assert stack(env) == ["List"]
    assert env.snapshot() == before
    assert env.log[-1].kind == "ui"


def test_cancel_an_edit_returns_to_the_detail(env: Environment) -> None:
    before = env.snapshot()
    ok(env.call("user", "open_reminder", {"reminder_id": "rem-vitamins"}))
    ok(env.call("user", "edit"))
    ok(env.call("user", "set_title", {"title": "Take iron"}))
    ok(env.call("user", "set_repetition", {"repetition": "none"}))
    ok(env.call("user", "cancel"))
    assert screen_of(env) == "Detail"
    assert stack(env) == ["List", "Detail"]
    assert ok(env.call("user", "refresh"))["title"] == "Take vitamins"
    assert env.snapshot() == before


def test_unknown_argument_is_rejected_and_the_draft_kept(env: Environment) -> None:
    ok(env.call("user", "create_new"))
    ok(env.call("user", "set_title", {"title": "Draft"}))
    err(env.call("user", "set_title", {"title": "x", "colour": "red"}), "unexpected argument 'colour'")
    err(env.call("user", "set_due_datetime", {"due_datetime": "someday"}), "due_datetime")
    draft = ok(env.call("user", "set_description", {"description": ""}))
    assert (draft["title"], draft["due_datetime"]) == ("Draft", "2025-03-03T10:00:00Z")


# -- agent API -------------------------------------------------------------------------------------


def test_agent_reads(env: Environment) -> None:
    assert ids(agent(env, "get_all_reminders")) == ALL
    assert ids(agent(env, "get_due_reminders")) == DUE
    upcoming = agent(env, "get_upcoming_reminders", limit=4)
    assert ids(upcoming["reminders"]) == UPCOMING[:4]
    assert upcoming["total"] == 11
    assert ids(agent(env, "get_upcoming_reminders")["reminders"]) == UPCOMING[:PAGE]
    shown = agent(env, "get_reminder", reminder_id="rem-plants")
    assert shown == {
        "reminder_id": "rem-plants",
        "title": "Water the neighbours' plants",
        "description": "Ferns twice as much; key under the mat",
        "due_datetime": "2025-03-08T10:00:00Z",
        "repetition": "weekly",
        "repeat_until": "2025-03-22T23:59:00Z",
        "set_for": "2025-03-08T10:00:00Z",
        "announced": False,
    }
    assert [e.kind for e in env.log[-5:]] == ["read"] * 5


def test_add_reminder(env: Environment) -> None:
    new_id = agent(
        env,
        "add_reminder",
        title=" Pick up the dry cleaning ",
        due_datetime="2025-03-04 17:00",
        description=" Ticket 4411 ",
    )["id"]
    assert new_id == "reminder-1"
    assert env.log[-1].result == {
        "done": "Added reminder reminder-1 'Pick up the dry cleaning', due Tue 2025-03-04 17:00.",
        "id": "reminder-1",
    }
    assert reminders(env)[new_id] == {
        "reminder_id": new_id,
        "title": "Pick up the dry cleaning",
        "description": "Ticket 4411",
        "due_datetime": "2025-03-04T17:00:00Z",
        "repetition": "none",
        "repeat_until": None,
        "set_for": "2025-03-04T17:00:00Z",
        "announced": False,
    }
    assert env.log[-1].kind == "write"
    second = agent(
        env,
        "add_reminder",
        title="Team retro",
        due_datetime="2025-03-07T16:00:00+01:00",
        repetition="WEEKLY",
        repeat_until="2025-04-30 00:00",
    )["id"]
    assert second == "reminder-2"
    stored = reminders(env)[second]
    assert (stored["due_datetime"], stored["repetition"], stored["repeat_until"]) == (
        "2025-03-07T15:00:00Z",
        "weekly",
        "2025-04-30T00:00:00Z",
    )
    agent(env, "delete_reminder", reminder_id=second)
    assert (
        agent(env, "add_reminder", title="Again", due_datetime="2025-03-05 10:00")["id"] == "reminder-3"
    )  # not reused


def test_update_reminder(env: Environment) -> None:
    updated = agent(
        env,
        "update_reminder",
        reminder_id="rem-slides",
        updates={"title": " Send slides to Alice ", "description": None},
    )
    assert (updated["title"], updated["description"]) == ("Send slides to Alice", "")
    assert updated["due_datetime"] == "2025-03-04T15:00:00Z"  # kept
    assert reminders(env)["rem-slides"] == updated
    # stopping a repetition also drops its end
    updated = agent(env, "update_reminder", reminder_id="rem-plants", updates={"repetition": "None"})
    assert (updated["repetition"], updated["repeat_until"]) == ("none", None)
    # repeat forever
    agent(env, "update_reminder", reminder_id="rem-plants", updates={"repetition": "weekly"})
    updated = agent(
        env, "update_reminder", reminder_id="rem-plants", updates={"repeat_until": "2025-04-01 00:00"}
    )
    assert updated["repeat_until"] == "2025-04-01T00:00:00Z"
    updated = agent(env, "update_reminder", reminder_id="rem-plants", updates={"repeat_until": None})
    assert (updated["repetition"], updated["repeat_until"]) == ("weekly", None)
    assert env.log[-1].kind == "write"


def test_delete_reminder(env: Environment) -> None:
    assert "Renew passport" in agent(env, "delete_reminder", reminder_id="rem-passport")
    assert "rem-passport" not in reminders(env)
    assert len(reminders(env)) == len(ALL) - 1


@pytest.mark.parametrize(
    ("tool", "args", "message"),
    [
        ("get_reminder", {"reminder_id": "ghost"}, "no reminder with id 'ghost'"),
        ("get_upcoming_reminders", {"limit": 0}, "between 1 and 100"),
        ("get_upcoming_reminders", {"limit": 101}, "between 1 and 100"),
        ("add_reminder", {"title": " ", "due_datetime": "2025-03-04 10:00"}, "needs a title"),
        ("add_reminder", {"title": "No time"}, "due_datetime"),
        ("add_reminder", {"title": "Vague", "due_datetime": "tomorrow morning"}, "due_datetime"),
        (
            "add_reminder",
            {"title": "Often", "due_datetime": "2025-03-04 10:00", "repetition": "fortnightly"},
            "repetition",
        ),
        (
            "add_reminder",
            {"title": "Once", "due_datetime": "2025-03-04 10:00", "repeat_until": "2025-03-10 10:00"},
            "only applies to a repeating reminder",
        ),
        (
            "add_reminder",
            {
                "title": "Backwards",
                "due_datetime": "2025-03-04 10:00",
                "repetition": "daily",
                "repeat_until": "2025-03-04 09:59",
            },
            "must not be before the due time",
        ),
        ("add_reminder", {"title": "x", "due_datetime": "2025-03-04 10:00", "priority": "high"}, "priority"),
        ("update_reminder", {"reminder_id": "ghost", "updates": {"title": "x"}}, "ghost"),
        ("update_reminder", {"reminder_id": "rem-tax", "updates": {}}, "no field"),
        ("update_reminder", {"reminder_id": "rem-tax", "updates": {"title": " "}}, "cannot be empty"),
        ("update_reminder", {"reminder_id": "rem-tax", "updates": {"title": None}}, "cannot be removed"),
        (
            "update_reminder",
            {"reminder_id": "rem-tax", "updates": {"due_datetime": None}},
            "cannot be removed",
        ),
        ("update_reminder", {"reminder_id": "rem-rent", "updates": {"repetition": None}}, 'use "none"'),
        ("update_reminder", {"reminder_id": "rem-tax", "updates": {"due_datetime": "soon"}}, "due_datetime"),
        ("update_reminder", {"reminder_id": "rem-tax", "updates": {"repetition": "hourly"}}, "repetition"),
        (
            "update_reminder",
            {"reminder_id": "rem-tax", "updates": {"repeat_until": "2025-04-30 00:00"}},
            "only applies to a repeating reminder",
        ),
        (
            "update_reminder",
            {"reminder_id": "rem-plants", "updates": {"due_datetime": "2025-03-30 10:00"}},
            "must not be before the due time",
        ),
        (
            "update_reminder",
            {
                "reminder_id": "rem-plants",
                "updates": {"repetition": "none", "repeat_until": "2025-03-22 23:59"},
            },
            "only applies to a repeating reminder",
        ),
        ("update_reminder", {"reminder_id": "rem-tax", "updates": {"announced": True}}, "updates.announced"),
        ("delete_reminder", {"reminder_id": "ghost"}, "ghost"),
    ],
)
def test_agent_api_errors_change_nothing(env: Environment, tool: str, args: dict, message: str) -> None:
    before = env.snapshot()
    err(env.call("assistant", f"reminder__{tool}", args, mode="execute"), message)
    assert env.snapshot() == before


def test_the_assistant_cannot_announce_reminders(env: Environment) -> None:
    env.advance(timedelta(hours=5))  # the dentist reminder is due
    agent(env, "update_reminder", reminder_id="rem-tax", updates={"due_datetime": "2025-03-03 13:30"})
    before = env.snapshot()
    err(env.call("assistant", "reminder__announce_due_reminders", {}, mode="execute"))
    assert env.snapshot() == before


# -- reminders falling due -------------------------------------------------------------------------


def test_next_wakeup_is_the_earliest_unannounced_due_time(env: Environment) -> None:
    app = env.apps["reminder"]
    assert app.next_wakeup() == datetime(2025, 3, 3, 13, 0, tzinfo=UTC)  # announced ones are left out
    assert env.next_event_time() == datetime(2025, 3, 3, 13, 0, tzinfo=UTC)
    agent(env, "delete_reminder", reminder_id="rem-dentist")
    assert app.next_wakeup() == datetime(2025, 3, 4, 8, 0, tzinfo=UTC)
    empty = make_env(["reminder"])
    assert empty.apps["reminder"].next_wakeup() is None
    assert empty.next_event_time() is None


def test_a_one_off_reminder_is_announced_once_at_its_time(env: Environment) -> None:
    clear_notifications(env)
    env.advance(timedelta(hours=3, minutes=59))  # 12:59
    assert env.user_view().notifications == []
    assert env.assistant_observation().notifications == []
    env.advance(timedelta(minutes=10))  # 13:09
    user = env.user_view().notifications
    assert user == [
        "[2025-03-03 13:00] Reminders: Reminder: Leave for the dentist: Appointment at 14:00, Smile Dental, "
        "12 Oak St"
    ]
    assistant = env.assistant_observation().notifications
    assert assistant == [
        "[2025-03-03 13:00] Reminders: Reminder: Leave for the dentist\n"
        "Appointment at 14:00, Smile Dental, 12 Oak St\n(reminder_id=rem-dentist)"
    ]
    notification = env.notifications.inboxes["assistant"].items[-1]
    assert (notification.kind, notification.data) == ("reminder_due", {"reminder_id": "rem-dentist"})
    entry = next(e for e in env.log if e.tool == "announce_due_reminders")
    assert (entry.actor, entry.app, entry.event_id, entry.ok) == (
        "env",
        "reminder",
        "reminder:announce_due_reminders",
        True,
    )
    assert entry.result == ["rem-dentist"]
    assert entry.time == datetime(2025, 3, 3, 13, 0, tzinfo=UTC)
    stored = reminders(env)["rem-dentist"]
    assert (stored["announced"], stored["due_datetime"]) == (True, "2025-03-03T13:00:00Z")
    assert ids(agent(env, "get_due_reminders")) == [*DUE, "rem-dentist"]
    env.advance(timedelta(hours=5))  # nothing more until tomorrow's vitamins
    assert announced(env) == [("03-03 13:00", "rem-dentist")]


def test_a_notification_is_truncated_for_the_user_only(env: Environment) -> None:
    env.advance(timedelta(days=2, minutes=1))  # past the rent on Wednesday 09:00
    clear_notifications(env)
    agent(env, "update_reminder", reminder_id="rem-rent", updates={"due_datetime": "2025-03-05 09:30"})
    env.advance(timedelta(minutes=30))
    user = env.user_view().notifications
    assert user == [
        "[2025-03-05 09:30] Reminders: Reminder: Pay rent: Transfer 1,450 to Bob Okafor (landlord) by bank "
        "transfer, reference MARCH-RENT-12B, account …"
    ]
    assistant = env.assistant_observation().notifications
    assert assistant == [
        f"[2025-03-05 09:30] Reminders: Reminder: Pay rent\n{RENT_NOTE}\n(reminder_id=rem-rent)"
    ]


def test_a_reminder_without_description(env: Environment) -> None:
    env.advance(timedelta(days=1))  # Tuesday 08:00: vitamins
    assert env.user_view().notifications[-1] == "[2025-03-04 08:00] Reminders: Reminder: Take vitamins"
    assert env.assistant_observation().notifications[-1] == (
        "[2025-03-04 08:00] Reminders: Reminder: Take vitamins\n(reminder_id=rem-vitamins)"
    )


def test_a_daily_reminder_repeats_every_day(env: Environment) -> None:
    env.advance(timedelta(days=3))  # to Thursday 09:00
    assert announced(env) == [
        ("03-03 13:00", "rem-dentist"),
        ("03-04 08:00", "rem-vitamins"),
        ("03-04 15:00", "rem-slides"),
        ("03-05 08:00", "rem-vitamins"),
        ("03-05 09:00", "rem-rent"),
        ("03-05 19:00", "rem-recycling"),
        ("03-06 08:00", "rem-vitamins"),
    ]
    stored = reminders(env)
    assert (stored["rem-vitamins"]["due_datetime"], stored["rem-vitamins"]["announced"]) == (
        "2025-03-07T08:00:00Z",
        False,
    )
    assert (stored["rem-rent"]["due_datetime"], stored["rem-rent"]["announced"]) == (
        "2025-04-05T09:00:00Z",
        False,
    )
    assert stored["rem-recycling"]["due_datetime"] == "2025-03-12T19:00:00Z"
    assert (stored["rem-slides"]["due_datetime"], stored["rem-slides"]["announced"]) == (
        "2025-03-04T15:00:00Z",
        True,
    )
    wakes = [e for e in env.log if e.tool == "announce_due_reminders"]
    assert len(wakes) == 7
    assert all(e.actor == "env" and e.event_id == "reminder:announce_due_reminders" for e in wakes)
    # repeating reminders are never listed as due: they have moved on to their next time
    assert ids(agent(env, "get_due_reminders")) == [*DUE, "rem-dentist", "rem-slides"]


def test_a_weekly_reminder_stops_after_repeat_until(env: Environment) -> None:
    env.advance(timedelta(days=27))  # to Sunday 2025-03-30
    plants = [when for when, rid in announced(env) if rid == "rem-plants"]
    assert plants == ["03-08 10:00", "03-15 10:00", "03-22 10:00"]
    stored = reminders(env)["rem-plants"]
    assert (stored["due_datetime"], stored["announced"]) == ("2025-03-22T10:00:00Z", True)
    assert "rem-plants" in ids(agent(env, "get_due_reminders"))
    assert env.apps["reminder"].next_wakeup() == datetime(2025, 3, 31, 8, 0, tzinfo=UTC)  # the vitamins
    # the yearly birthday moved a year on
    assert reminders(env)["rem-dana-bday"]["due_datetime"] == "2026-03-14T08:00:00Z"
    assert [when for when, rid in announced(env) if rid == "rem-dana-bday"] == ["03-14 08:00"]


def test_extending_repeat_until_resumes_a_stopped_reminder(env: Environment) -> None:
    env.advance(timedelta(days=27))  # Sunday 2025-03-30 09:00; the plants stopped on the 22nd
    updated = agent(
        env, "update_reminder", reminder_id="rem-plants", updates={"repeat_until": "2025-04-30 00:00"}
    )
    assert (updated["due_datetime"], updated["announced"]) == ("2025-04-05T10:00:00Z", False)
    env.advance(timedelta(days=7))
    assert [when for when, rid in announced(env) if rid == "rem-plants"][-1] == "04-05 10:00"


def test_a_monthly_reminder_keeps_its_day_clamped_to_the_month_end(env: Environment) -> None:
    env.advance_to(datetime(2025, 4, 1, tzinfo=UTC))
    stored = reminders(env)["rem-car-loan"]
    assert (stored["due_datetime"], stored["announced"]) == ("2025-04-30T12:00:00Z", False)
    assert ("03-31 12:00", "rem-car-loan") in announced(env)


def test_moving_the_due_time_rearms_an_announced_reminder(env: Environment) -> None:
    env.advance(timedelta(hours=5))  # 14:00, the dentist reminder was announced at 13:00
    clear_notifications(env)
    updated = agent(
        env, "update_reminder", reminder_id="rem-dentist", updates={"due_datetime": "2025-03-03 16:00"}
    )
    assert updated["announced"] is False
    assert env.apps["reminder"].next_wakeup() == datetime(2025, 3, 3, 16, 0, tzinfo=UTC)
    env.advance(timedelta(hours=3))
    assert announced(env)[-1] == ("03-03 16:00", "rem-dentist")
    assert len(env.assistant_observation().notifications) == 1
    assert reminders(env)["rem-dentist"]["announced"] is True


def test_the_user_moving_the_due_time_rearms_it_too(env: Environment) -> None:
    env.advance(timedelta(hours=5))
    ok(env.call("user", "open_reminder", {"reminder_id": "rem-dentist"}))
    ok(env.call("user", "edit"))
    ok(env.call("user", "set_due_datetime", {"due_datetime": "2025-03-03 15:30"}))
    assert ok(env.call("user", "save"))["announced"] is False
    env.advance(timedelta(hours=2))
    assert [when for when, rid in announced(env) if rid == "rem-dentist"] == ["03-03 13:00", "03-03 15:30"]


def test_other_edits_do_not_rearm_an_announced_reminder(env: Environment) -> None:
    env.advance(timedelta(hours=5))
    agent(
        env, "update_reminder", reminder_id="rem-dentist", updates={"title": "Dentist", "description": "done"}
    )
    assert reminders(env)["rem-dentist"]["announced"] is True
    assert env.apps["reminder"].next_wakeup() == datetime(2025, 3, 4, 8, 0, tzinfo=UTC)


def test_making_an_announced_reminder_repeat_waits_for_its_next_occurrence(env: Environment) -> None:
    # "Call Mom back" was due and announced on Sunday at 18:00; from now on, every day
    updated = agent(env, "update_reminder", reminder_id="rem-call-mom", updates={"repetition": "daily"})
    assert (updated["due_datetime"], updated["announced"]) == ("2025-03-03T18:00:00Z", False)
    env.advance(timedelta(hours=10))
    assert ("03-03 18:00", "rem-call-mom") in announced(env)
    assert reminders(env)["rem-call-mom"]["due_datetime"] == "2025-03-04T18:00:00Z"


def test_a_deleted_reminder_is_never_announced(env: Environment) -> None:
    agent(env, "delete_reminder", reminder_id="rem-dentist")
    env.advance(timedelta(hours=12))
    assert announced(env) == []


def test_a_reminder_added_for_a_past_time_is_announced_at_once(env: Environment) -> None:
    new_id = agent(env, "add_reminder", title="Take the pizza out", due_datetime="2025-03-03 08:55")["id"]
    env.deliver_due_events()
    assert announced(env) == [("03-03 09:00", new_id)]
    assert reminders(env)[new_id]["announced"] is True


def test_a_seeded_overdue_reminder_not_yet_announced_is_announced_first() -> None:
    seed = {
        "reminder": {
            "reminders": {
                "r-late": reminder("r-late", "Move the car", "2025-03-03 07:00"),
                "r-gym": reminder("r-gym", "Gym", "2025-02-24 07:00", repetition="weekly"),
            }
        }
    }
    env = make_env(["reminder"], seed)
    env.deliver_due_events()
    # both at the current time, in due order; the weekly one skips to its next time after now
    assert announced(env) == [("03-03 09:00", "r-gym"), ("03-03 09:00", "r-late")]
    assert reminders(env)["r-gym"]["due_datetime"] == "2025-03-10T07:00:00Z"
    assert len([e for e in env.log if e.tool == "announce_due_reminders"]) == 1


def test_announcing_with_nothing_due_changes_nothing(env: Environment) -> None:
    before = env.snapshot()
    assert ok(env.call("env", "reminder__announce_due_reminders", {})) == []
    assert env.snapshot() == before
    assert env.assistant_observation().notifications == []


@pytest.mark.parametrize(
    ("due", "repetition", "after", "expected"),
    [
        ("2025-03-03 08:00", "none", "2025-03-03 09:00", None),
        ("2025-03-03 08:00", "daily", "2025-03-03 08:00", "2025-03-04 08:00"),
        ("2025-03-01 08:00", "daily", "2025-03-03 09:00", "2025-03-04 08:00"),
        ("2025-03-01 08:00", "daily", "2025-03-03 08:00", "2025-03-04 08:00"),  # strictly after
        ("2025-03-03 08:00", "weekly", "2025-03-17 08:00", "2025-03-24 08:00"),
        ("2025-03-03 08:00", "daily", "2025-03-01 00:00", "2025-03-04 08:00"),  # always after the due time
        ("2025-01-31 09:00", "monthly", "2025-01-31 09:00", "2025-02-28 09:00"),
        ("2024-01-31 09:00", "monthly", "2024-02-01 00:00", "2024-02-29 09:00"),
        ("2025-01-31 09:00", "monthly", "2025-04-15 00:00", "2025-04-30 09:00"),
        ("2025-03-15 09:00", "monthly", "2025-03-15 09:30", "2025-04-15 09:00"),
        ("2025-12-15 09:00", "monthly", "2025-12-20 00:00", "2026-01-15 09:00"),
        ("2024-02-29 09:00", "yearly", "2024-03-01 00:00", "2025-02-28 09:00"),
        ("2025-12-31 09:00", "yearly", "2026-01-01 00:00", "2026-12-31 09:00"),
        ("2020-03-14 08:00", "yearly", "2025-03-14 08:00", "2026-03-14 08:00"),
    ],
)
def test_next_occurrence(due: str, repetition: str, after: str, expected: str | None) -> None:
    def moment(text: str) -> datetime:
        return datetime.fromisoformat(text).replace(tzinfo=UTC)

    found = next_occurrence(moment(due), Repetition(repetition), moment(after))
    assert found == (None if expected is None else moment(expected))


# -- a careless user -------------------------------------------------------------------------------


def test_a_random_user_walks_every_screen() -> None:
    env = make_env(["reminder"], SEED)
    user = RandomUser(random.Random(0))
    for step in range(3000):
        user.step(env)
        if step % 300 == 0:
            env.advance(timedelta(hours=7))  # reminders fall due while the user taps around
    tried = {e.tool for e in env.log if e.actor == "user"}
    for screen in type(env.apps["reminder"]).screens:
        assert set(screen.actions) <= tried
    assert sum(e.ok for e in env.log) / len(env.log) > 0.7


def test_set_for_keeps_the_time_a_repeating_reminder_was_set_for_as_it_fires() -> None:
    """A check on the final state can tell a daily reminder set for tomorrow from one set for next week,
    although both have moved on by the time the episode ends."""
    env = make_env(["reminder"])
    new_id = agent(env, "add_reminder", title="Stretch", due_datetime="2025-03-04 08:00", repetition="daily")[
        "id"
    ]
    env.advance_to(datetime(2025, 3, 6, 9, 0, tzinfo=UTC))
    stored = reminders(env)[new_id]
    assert stored["due_datetime"] == "2025-03-07T08:00:00Z"
    assert stored["set_for"] == "2025-03-04T08:00:00Z"
    agent(env, "update_reminder", reminder_id=new_id, updates={"due_datetime": "2025-03-09 07:00"})
    assert reminders(env)[new_id]["set_for"] == "2025-03-09T07:00:00Z"
