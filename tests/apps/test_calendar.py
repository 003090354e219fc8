from __future__ import annotations

from datetime import timedelta

import pytest

from pare.apps.calendar import Agenda, EventEdit
from pare.env import Environment
from pare.errors import UserInputError
from tests.conftest import err, make_env, ok, screen_of


def event(event_id: str, title: str, start: str, end: str, **fields: object) -> dict:
    """A seed event; ``start`` and ``end`` are "MM-DD HH:MM" in March 2025, UTC."""
    return {
        "event_id": event_id,
        "title": title,
        "start_datetime": f"2025-{start.replace(' ', 'T')}:00Z",
        "end_datetime": f"2025-{end.replace(' ', 'T')}:00Z",
        **fields,
    }


ALICE_BOB = ["Alice Chen", "Bob Okafor"]
# The episode starts on Monday 2025-03-03 at 09:00 UTC. A week of events, with distractors whose titles
# look alike (three standups, two dentist events, a review and the preparation of the review).
# fmt: off
EVENTS = [
    event("ev-migration", "Server migration", "03-02 23:00", "03-03 01:00", tag="work",
          attendees=["Bob Okafor"]),
    event("ev-standup-mon", "Team standup", "03-03 09:30", "03-03 09:45", tag="work", location="Zoom",
          attendees=ALICE_BOB),
    event("ev-planning", "Sprint planning", "03-03 11:00", "03-03 12:00", tag="work", location="Room 4B",
          attendees=["Alice Chen", "Eve Moreau"]),
    event("ev-dentist", "Dentist appointment", "03-03 14:00", "03-03 15:00", tag="health",
          location="Smile Dental, 12 Oak St", description="Routine cleaning"),
    event("ev-standup-tue", "Team standup", "03-04 09:30", "03-04 09:45", tag="work", location="Zoom",
          attendees=ALICE_BOB),
    event("ev-lunch-carol", "Lunch with Carol", "03-04 12:30", "03-04 13:30", tag="family",
          location="Luigi's", attendees=["Carol Chen"]),
    event("ev-prep", "Prepare quarterly review slides", "03-04 16:00", "03-04 17:00", tag="work"),
    event("ev-standup-wed", "Team standup", "03-05 09:30", "03-05 09:45", tag="work", location="Zoom",
          attendees=ALICE_BOB),
    event("ev-team-lunch", "Team lunch", "03-05 12:00", "03-05 13:00", tag="work", location="Noodle Bar",
          attendees=[*ALICE_BOB, "Dana Park"]),
    event("ev-review", "Quarterly review", "03-05 15:00", "03-05 16:30", tag="work", location="Board room",
          description="Q1 numbers, bring the slides", attendees=["Alice Chen"]),
    event("ev-dentist-call", "Call dentist about follow-up", "03-06 11:00", "03-06 11:15", tag="health"),
    event("ev-yoga", "Yoga class", "03-06 18:00", "03-06 19:00", tag="health", location="Studio 5"),
    event("ev-dinner", "Dinner with parents", "03-07 19:00", "03-07 21:30", tag="family", location="Home",
          attendees=["Mom", "Dad"]),
    event("ev-flight", "Flight to Lisbon", "03-08 22:00", "03-09 01:30", tag="travel",
          location="SFO Terminal 2", description="TP 238, seat 14C"),
    event("ev-brunch", "Brunch", "03-09 11:00", "03-09 12:30", attendees=["Carol Chen"]),
]
# fmt: on
SEED = {"calendar": {"events": {e["event_id"]: e for e in EVENTS}}}
MONDAY = ["ev-migration", "ev-standup-mon", "ev-planning", "ev-dentist"]


@pytest.fixture
def env() -> Environment:
    env = make_env(["calendar"], SEED)
    ok(env.call("user", "open_app", {"app_name": "calendar"}))
    return env


def events(env: Environment) -> dict:
    return env.snapshot()["calendar"]["events"]


def ids(listing: list[dict]) -> list[str]:
    return [e["event_id"] for e in listing]


def stack(env: Environment) -> list[str]:
    return [s.screen_name() for s in env.system.stacks["calendar"]]


def agent(env: Environment, tool: str, **args: object) -> object:
    return ok(env.call("assistant", f"calendar__{tool}", args, mode="execute"))


# -- seed data -----------------------------------------------------------------------------------------


def test_seed_rejects_an_event_ending_before_it_starts() -> None:
    bad = event("x", "Backwards", "03-03 10:00", "03-03 09:00")
    with pytest.raises(UserInputError, match="must end after it starts"):
        make_env(["calendar"], {"calendar": {"events": {"x": bad}}})


def test_seed_rejects_an_event_stored_under_another_id() -> None:
    good = event("x", "Fine", "03-03 10:00", "03-03 11:00")
    with pytest.raises(UserInputError, match="has event_id 'x'"):
        make_env(["calendar"], {"calendar": {"events": {"y": good}}})


# -- Agenda ----------------------------------------------------------------------------------------


def test_opens_on_the_agenda(env: Environment) -> None:
    assert screen_of(env) == "Agenda"


def test_the_agenda_opens_on_the_simulated_day_and_says_which() -> None:
    env = make_env(["calendar"], SEED)
    env.advance(timedelta(days=2))
    ok(env.call("user", "open_app", {"app_name": "calendar"}))
    assert env.system.current_screen().label() == "Agenda(day='2025-03-05', tag=None, attendee=None)"


def test_list_events_shows_today_sorted_by_start(env: Environment) -> None:
    shown = ok(env.call("user", "list_events"))
    assert shown["day"] == "2025-03-03"
    assert ids(shown["events"]) == MONDAY  # the migration started on Sunday night
    assert shown["tag"] is None and shown["attendee"] is None
    assert screen_of(env) == "Agenda"
    assert env.log[-1].kind == "read"


def test_set_day_changes_the_listing(env: Environment) -> None:
    shown = ok(env.call("user", "set_day", {"day": "2025-03-05"}))
    assert shown["day"] == "Wed 2025-03-05"
    assert ids(shown["events"]) == ["ev-standup-wed", "ev-team-lunch", "ev-review"]
    assert ids(ok(env.call("user", "list_events"))["events"]) == [
        "ev-standup-wed",
        "ev-team-lunch",
        "ev-review",
    ]
    # an event over midnight shows on both days
    assert ids(ok(env.call("user", "set_day", {"day": "2025-03-08"}))["events"]) == ["ev-flight"]
    assert ids(ok(env.call("user", "set_day", {"day": "2025-03-09"}))["events"]) == ["ev-flight", "ev-brunch"]
    assert ok(env.call("user", "set_day", {"day": "2025-03-10"}))["events"] == []
    assert screen_of(env) == "Agenda"


def test_set_day_rejects_a_non_date(env: Environment) -> None:
    err(env.call("user", "set_day", {"day": "next tuesday"}), "day")
    assert ok(env.call("user", "list_events"))["day"] == "2025-03-03"


def test_filter_by_tag(env: Environment) -> None:
    shown = ok(env.call("user", "filter_by_tag", {"tag": "WORK"}))
    assert ids(shown["events"]) == ["ev-migration", "ev-standup-mon", "ev-planning"]
    assert shown["tag"] == "WORK"
    assert ids(ok(env.call("user", "list_events"))["events"]) == [
        "ev-migration",
        "ev-standup-mon",
        "ev-planning",
    ]
    ok(env.call("user", "set_day", {"day": "2025-03-06"}))
    assert ids(ok(env.call("user", "list_events"))["events"]) == []  # the filter stays on another day
    ok(env.call("user", "filter_by_tag", {"tag": "health"}))
    assert ids(ok(env.call("user", "list_events"))["events"]) == ["ev-dentist-call", "ev-yoga"]
    cleared = ok(env.call("user", "filter_by_tag", {"tag": ""}))
    assert "tag" not in cleared  # the agenda names a filter only while one is on
    assert ids(cleared["events"]) == ["ev-dentist-call", "ev-yoga"]
    assert screen_of(env) == "Agenda"


def test_filter_by_unknown_tag_is_an_error_and_keeps_the_filter(env: Environment) -> None:
    ok(env.call("user", "filter_by_tag", {"tag": "health"}))
    err(env.call("user", "filter_by_tag", {"tag": "gym"}), "no event has the tag 'gym'", "family, health")
    assert ok(env.call("user", "list_events"))["tag"] == "health"


def test_filter_by_attendee(env: Environment) -> None:
    shown = ok(env.call("user", "filter_by_attendee", {"attendee": "alice"}))
    assert ids(shown["events"]) == ["ev-standup-mon", "ev-planning"]
    assert shown["attendee"] == "alice"
    ok(env.call("user", "filter_by_attendee", {"attendee": "Eve Moreau"}))
    assert ids(ok(env.call("user", "list_events"))["events"]) == ["ev-planning"]
    # both filters at once
    ok(env.call("user", "filter_by_attendee", {"attendee": "bob"}))
    ok(env.call("user", "filter_by_tag", {"tag": "work"}))
    assert ids(ok(env.call("user", "list_events"))["events"]) == ["ev-migration", "ev-standup-mon"]
    cleared = ok(env.call("user", "filter_by_attendee", {"attendee": "  "}))
    assert "attendee" not in cleared
    assert ids(cleared["events"]) == ["ev-migration", "ev-standup-mon", "ev-planning"]
    err(
        env.call("user", "filter_by_attendee", {"attendee": "Zed"}), "no event has an attendee matching 'zed'"
    )
    assert ok(env.call("user", "list_events"))["attendee"] is None
    assert screen_of(env) == "Agenda"


def test_search_events_matches_every_word(env: Environment) -> None:
    found = ok(env.call("user", "search_events", {"query": "dentist"}))
    assert ids(found) == ["ev-dentist", "ev-dentist-call"]
    assert ids(ok(env.call("user", "search_events", {"query": "quarterly review"}))) == [
        "ev-prep",
        "ev-review",
    ]
    assert ids(ok(env.call("user", "search_events", {"query": "DANA lunch"}))) == ["ev-team-lunch"]
    assert ids(ok(env.call("user", "search_events", {"query": "slides q1"}))) == ["ev-review"]  # description
    assert ids(ok(env.call("user", "search_events", {"query": "terminal"}))) == ["ev-flight"]  # location
    assert ids(ok(env.call("user", "search_events", {"query": "travel"}))) == ["ev-flight"]  # tag
    assert ok(env.call("user", "search_events", {"query": "karaoke"})) == []
    err(env.call("user", "search_events", {"query": " "}), "empty")
    assert screen_of(env) == "Agenda"


def test_read_today_ignores_the_day_and_filters_shown(env: Environment) -> None:
    ok(env.call("user", "set_day", {"day": "2025-03-07"}))
    ok(env.call("user", "filter_by_tag", {"tag": "family"}))
    assert ids(ok(env.call("user", "read_today_calendar_events"))) == MONDAY
    assert screen_of(env) == "Agenda"
    env.advance(timedelta(days=1))
    assert ids(ok(env.call("user", "read_today_calendar_events"))) == [
        "ev-standup-tue",
        "ev-lunch-carol",
        "ev-prep",
    ]


def test_today_follows_the_simulated_clock(env: Environment) -> None:
    env.advance(timedelta(days=2))
    # the agenda stays on the day it shows (it opened on Monday), today's events follow the clock
    assert ok(env.call("user", "list_events"))["day"] == "2025-03-03"
    today = ["ev-standup-wed", "ev-team-lunch", "ev-review"]
    assert ids(ok(env.call("user", "read_today_calendar_events"))) == today
    assert ids(agent(env, "read_today_calendar_events")) == today
    # an agenda that lost its day (None) shows today's
    env.system.stacks["calendar"][-1] = Agenda()
    shown = ok(env.call("user", "list_events"))
    assert shown["day"] == "2025-03-05"
    assert ids(shown["events"]) == today


def test_get_all_tags(env: Environment) -> None:
    assert ok(env.call("user", "get_all_tags")) == ["family", "health", "travel", "work"]
    assert screen_of(env) == "Agenda"


def test_open_event_goes_to_detail(env: Environment) -> None:
    shown = ok(env.call("user", "open_event", {"event_id": "ev-review"}))
    assert shown["title"] == "Quarterly review"
    assert screen_of(env) == "Detail"
    assert stack(env) == ["Agenda", "Detail"]


def test_open_unknown_event_is_an_error_and_stays(env: Environment) -> None:
    err(env.call("user", "open_event", {"event_id": "ev-nope"}), "no event with id 'ev-nope'")
    assert screen_of(env) == "Agenda"


def test_open_event_by_index_uses_the_filtered_listing(env: Environment) -> None:
    ok(env.call("user", "filter_by_attendee", {"attendee": "alice"}))
    shown = ok(env.call("user", "open_event_by_index", {"index": 1}))
    assert shown["event_id"] == "ev-planning"
    assert screen_of(env) == "Detail"
    assert ok(env.call("user", "refresh"))["event_id"] == "ev-planning"


@pytest.mark.parametrize("index", [2, -1])
def test_open_event_by_index_out_of_range(env: Environment, index: int) -> None:
    ok(env.call("user", "filter_by_attendee", {"attendee": "alice"}))
    err(env.call("user", "open_event_by_index", {"index": index}), f"no event at position {index}", "0 to 1")
    assert screen_of(env) == "Agenda"


def test_open_event_by_index_on_an_empty_day(env: Environment) -> None:
    ok(env.call("user", "set_day", {"day": "2025-03-12"}))
    err(env.call("user", "open_event_by_index", {"index": 0}), "no events")
    assert screen_of(env) == "Agenda"


# -- Detail ----------------------------------------------------------------------------------------


def test_detail_refresh_and_list_attendees(env: Environment) -> None:
    ok(env.call("user", "open_event", {"event_id": "ev-team-lunch"}))
    assert ok(env.call("user", "list_attendees")) == ["Alice Chen", "Bob Okafor", "Dana Park"]
    assert ok(env.call("user", "refresh"))["location"] == "Noodle Bar"
    agent(env, "edit_calendar_event", event_id="ev-team-lunch", updates={"location": "Pizza Place"})
    assert ok(env.call("user", "refresh"))["location"] == "Pizza Place"
    assert screen_of(env) == "Detail"


def test_delete_returns_to_the_agenda(env: Environment) -> None:
    ok(env.call("user", "open_event", {"event_id": "ev-dentist"}))
    assert "ev-dentist" in ok(env.call("user", "delete"))
    assert screen_of(env) == "Agenda"
    assert stack(env) == ["Agenda"]
    assert "ev-dentist" not in events(env)
    assert env.log[-1].kind == "write"
    assert ids(ok(env.call("user", "list_events"))["events"]) == MONDAY[:-1]


def test_detail_of_an_event_deleted_meanwhile(env: Environment) -> None:
    ok(env.call("user", "open_event", {"event_id": "ev-dentist"}))
    agent(env, "delete_calendar_event", event_id="ev-dentist")
    before = env.snapshot()
    err(env.call("user", "refresh"), "no event with id 'ev-dentist'")
    err(env.call("user", "delete"), "no event with id 'ev-dentist'")
    err(env.call("user", "edit_event"), "no event with id 'ev-dentist'")
    assert env.snapshot() == before
    assert screen_of(env) == "Detail"


# -- Edit ------------------------------------------------------------------------------------------


def test_create_flow_from_the_agenda(env: Environment) -> None:
    before = len(events(env))
    draft = ok(env.call("user", "start_create_event"))
    assert screen_of(env) == "Edit"
    assert draft["event_id"] is None and draft["title"] is None
    assert draft["start_datetime"] == "2025-03-03T10:00:00Z"  # the next full hour, one hour long
    assert draft["end_datetime"] == "2025-03-03T11:00:00Z"
    ok(env.call("user", "set_title", {"title": "  Coffee with Dana "}))
    ok(
        env.call(
            "user",
            "set_time_range",
            {"start_datetime": "2025-03-04 15:00", "end_datetime": "2025-03-04 15:30"},
        )
    )
    ok(env.call("user", "set_tag", {"tag": "work"}))
    ok(env.call("user", "set_description", {"description": "Talk about the offsite"}))
    ok(env.call("user", "set_location", {"location": "Blue Bottle"}))
    draft = ok(env.call("user", "add_attendee", {"attendee": "Dana Park"}))
    assert draft["title"] == "Coffee with Dana"
    assert draft["attendees"] == ["Dana Park"]
    assert len(events(env)) == before  # nothing saved yet
    assert screen_of(env) == "Edit"

    saved = ok(env.call("user", "save"))
    assert env.log[-1].kind == "write"
    assert screen_of(env) == "Detail"
    assert stack(env) == ["Agenda", "Detail"]  # the Edit screen was replaced
    stored = events(env)[saved["event_id"]]
    assert stored == {
        "event_id": saved["event_id"],
        "title": "Coffee with Dana",
        "start_datetime": "2025-03-04T15:00:00Z",
        "end_datetime": "2025-03-04T15:30:00Z",
        "tag": "work",
        "description": "Talk about the offsite",
        "location": "Blue Bottle",
        "attendees": ["Dana Park"],
    }
    assert len(events(env)) == before + 1
    assert ok(env.call("user", "refresh"))["event_id"] == saved["event_id"]
    ok(env.call("user", "go_back"))
    assert screen_of(env) == "Agenda"
    ok(env.call("user", "set_day", {"day": "2025-03-04"}))
    assert saved["event_id"] in ids(ok(env.call("user", "list_events"))["events"])


def test_new_event_starts_at_the_next_full_hour(env: Environment) -> None:
    env.advance(timedelta(minutes=20))
    draft = ok(env.call("user", "start_create_event"))
    assert (draft["start_datetime"], draft["end_datetime"]) == (
        "2025-03-03T10:00:00Z",
        "2025-03-03T11:00:00Z",
    )


def test_save_without_a_title_is_an_error_and_stays(env: Environment) -> None:
    ok(env.call("user", "start_create_event"))
    before = env.snapshot()
    err(env.call("user", "save"), "no title", "set_title")
    assert env.snapshot() == before
    assert screen_of(env) == "Edit"
    err(env.call("user", "set_title", {"title": "   "}), "cannot be empty")
    assert screen_of(env) == "Edit"


def test_set_time_range_rejects_an_end_before_the_start(env: Environment) -> None:
    ok(env.call("user", "start_create_event"))
    err(
        env.call(
            "user",
            "set_time_range",
            {"start_datetime": "2025-03-04 15:00", "end_datetime": "2025-03-04 14:00"},
        ),
        "must be after the start",
    )
    err(
        env.call(
            "user",
            "set_time_range",
            {"start_datetime": "2025-03-04 15:00", "end_datetime": "2025-03-04 15:00"},
        ),
        "must be after the start",
    )
    screen = env.system.current_screen()
    assert isinstance(screen, EventEdit)
    draft = screen.draft()
    assert draft.start_datetime.isoformat() == "2025-03-03T10:00:00+00:00"  # unchanged


def test_time_zones_are_converted_to_utc(env: Environment) -> None:
    ok(env.call("user", "start_create_event"))
    ok(env.call("user", "set_title", {"title": "Call with Lisbon office"}))
    draft = ok(
        env.call(
            "user",
            "set_time_range",
            {"start_datetime": "2025-03-04T10:00:00+01:00", "end_datetime": "2025-03-04T11:00:00+01:00"},
        )
    )
    assert draft["start_datetime"] == "2025-03-04T09:00:00Z"
    saved = ok(env.call("user", "save"))
    assert events(env)[saved["event_id"]]["end_datetime"] == "2025-03-04T10:00:00Z"


def test_attendee_actions(env: Environment) -> None:
    ok(env.call("user", "start_create_event"))
    draft = ok(
        env.call("user", "set_attendees", {"attendees": ["Alice Chen", " ", "alice chen", "Bob Okafor"]})
    )
    assert draft["attendees"] == ["Alice Chen", "Bob Okafor"]
    err(env.call("user", "add_attendee", {"attendee": "ALICE CHEN"}), "already an attendee")
    err(env.call("user", "add_attendee", {"attendee": ""}), "empty")
    assert ok(env.call("user", "add_attendee", {"attendee": "Carol Chen"}))["attendees"] == [
        "Alice Chen",
        "Bob Okafor",
        "Carol Chen",
    ]
    assert ok(env.call("user", "remove_attendee", {"attendee": "bob okafor"}))["attendees"] == [
        "Alice Chen",
        "Carol Chen",
    ]
    err(
        env.call("user", "remove_attendee", {"attendee": "Bob Okafor"}),
        "not an attendee",
        "Alice Chen, Carol Chen",
    )
    err(env.call("user", "remove_attendee", {"attendee": "chen"}), "matches several attendees", "full name")
    assert ok(env.call("user", "remove_attendee", {"attendee": "carol"}))["attendees"] == ["Alice Chen"]
    err(env.call("user", "remove_attendee", {"attendee": " "}), "not an attendee")
    assert ok(env.call("user", "set_attendees", {"attendees": []}))["attendees"] == []
    err(env.call("user", "remove_attendee", {"attendee": "Alice Chen"}), "attendees: none")
    assert screen_of(env) == "Edit"


def test_clearing_optional_fields_in_the_draft(env: Environment) -> None:
    ok(env.call("user", "open_event", {"event_id": "ev-dentist"}))
    ok(env.call("user", "edit_event"))
    ok(env.call("user", "set_tag", {"tag": ""}))
    ok(env.call("user", "set_description", {"description": " "}))
    draft = ok(env.call("user", "set_location", {"location": ""}))
    assert (draft["tag"], draft["description"], draft["location"]) == (None, None, None)
    ok(env.call("user", "save"))
    stored = events(env)["ev-dentist"]
    assert (stored["tag"], stored["description"], stored["location"]) == (None, None, None)


def test_edit_flow_from_detail(env: Environment) -> None:
    ok(env.call("user", "open_event", {"event_id": "ev-planning"}))
    draft = ok(env.call("user", "edit_event"))
    assert screen_of(env) == "Edit"
    assert stack(env) == ["Agenda", "Detail", "Edit"]
    assert draft == {
        "event_id": "ev-planning",
        "title": "Sprint planning",
        "start_datetime": "2025-03-03T11:00:00Z",
        "end_datetime": "2025-03-03T12:00:00Z",
        "tag": "work",
        "description": None,
        "location": "Room 4B",
        "attendees": ["Alice Chen", "Eve Moreau"],
    }
    ok(
        env.call(
            "user",
            "set_time_range",
            {"start_datetime": "2025-03-03 13:00", "end_datetime": "2025-03-03 14:30"},
        )
    )
    ok(env.call("user", "set_location", {"location": "Room 2A"}))
    ok(env.call("user", "remove_attendee", {"attendee": "Eve Moreau"}))
    saved = ok(env.call("user", "save"))
    assert env.log[-1].kind == "write"
    assert saved["location"] == "Room 2A"
    assert screen_of(env) == "Detail"
    assert stack(env) == ["Agenda", "Detail"]
    assert ok(env.call("user", "refresh"))["event_id"] == "ev-planning"
    stored = events(env)["ev-planning"]
    assert (stored["start_datetime"], stored["end_datetime"]) == (
        "2025-03-03T13:00:00Z",
        "2025-03-03T14:30:00Z",
    )
    assert stored["attendees"] == ["Alice Chen"]
    assert stored["title"] == "Sprint planning"  # untouched fields are kept
    ok(env.call("user", "go_back"))
    assert screen_of(env) == "Agenda"


def test_saving_an_unchanged_event_writes_nothing(env: Environment) -> None:
    ok(env.call("user", "open_event", {"event_id": "ev-review"}))
    ok(env.call("user", "edit_event"))
    before = env.snapshot()
    writes = env.apps["calendar"].write_count
    ok(env.call("user", "save"))
    assert env.snapshot() == before
    assert env.apps["calendar"].write_count == writes
    assert env.log[-1].kind == "ui"
    assert screen_of(env) == "Detail"


def test_saving_an_edit_of_an_event_deleted_meanwhile_is_an_error(env: Environment) -> None:
    ok(env.call("user", "open_event", {"event_id": "ev-review"}))
    ok(env.call("user", "edit_event"))
    ok(env.call("user", "set_title", {"title": "Quarterly review (moved)"}))
    agent(env, "delete_calendar_event", event_id="ev-review")
    before = env.snapshot()
    err(env.call("user", "save"), "no event with id 'ev-review'")
    assert env.snapshot() == before
    assert screen_of(env) == "Edit"


def test_discard_a_new_event_changes_nothing(env: Environment) -> None:
    before = env.snapshot()
    ok(env.call("user", "start_create_event"))
    ok(env.call("user", "set_title", {"title": "Never saved"}))
    ok(env.call("user", "discard"))
    assert screen_of(env) == "Agenda"
    assert stack(env) == ["Agenda"]
    assert env.snapshot() == before


def test_discard_an_edit_changes_nothing(env: Environment) -> None:
    before = env.snapshot()
    ok(env.call("user", "open_event", {"event_id": "ev-yoga"}))
    ok(env.call("user", "edit_event"))
    ok(env.call("user", "set_title", {"title": "Pilates"}))
    ok(env.call("user", "set_attendees", {"attendees": ["Frank"]}))
    ok(env.call("user", "discard"))
    assert screen_of(env) == "Detail"
    assert ok(env.call("user", "refresh"))["title"] == "Yoga class"
    assert env.snapshot() == before


def test_unknown_argument_is_rejected_and_the_draft_kept(env: Environment) -> None:
    ok(env.call("user", "start_create_event"))
    ok(env.call("user", "set_title", {"title": "Draft"}))
    err(env.call("user", "set_title", {"title": "x", "colour": "red"}), "unexpected argument 'colour'")
    assert ok(env.call("user", "set_tag", {"tag": "work"}))["title"] == "Draft"


# -- agent API -------------------------------------------------------------------------------------


def test_agent_reads(env: Environment) -> None:
    assert agent(env, "get_calendar_event", event_id="ev-flight")["description"] == "TP 238, seat 14C"
    page = agent(
        env,
        "get_calendar_events_from_to",
        start_datetime="2025-03-04 00:00",
        end_datetime="2025-03-06 00:00",
        limit=3,
    )
    assert ids(page["events"]) == ["ev-standup-tue", "ev-lunch-carol", "ev-prep"]
    assert (page["total"], page["offset"]) == (6, 0)
    page = agent(
        env,
        "get_calendar_events_from_to",
        start_datetime="2025-03-04 00:00",
        end_datetime="2025-03-06 00:00",
        offset=3,
        limit=10,
    )
    assert ids(page["events"]) == ["ev-standup-wed", "ev-team-lunch", "ev-review"]
    # overlap, not containment: an event running across the window's start counts
    page = agent(
        env, "get_calendar_events_from_to", start_datetime="2025-03-09 00:00", end_datetime="2025-03-09 01:00"
    )
    assert ids(page["events"]) == ["ev-flight"]
    # an event ending exactly at the window's start does not
    page = agent(
        env, "get_calendar_events_from_to", start_datetime="2025-03-03 09:45", end_datetime="2025-03-03 11:00"
    )
    assert page["total"] == 0
    assert ids(agent(env, "read_today_calendar_events")) == MONDAY
    assert ids(agent(env, "search_events", query="standup zoom")) == [
        "ev-standup-mon",
        "ev-standup-tue",
        "ev-standup-wed",
    ]
    assert ids(agent(env, "search_events", query="carol")) == ["ev-lunch-carol", "ev-brunch"]
    assert agent(env, "get_all_tags") == ["family", "health", "travel", "work"]
    assert ids(agent(env, "get_calendar_events_by_tag", tag="Family")) == ["ev-lunch-carol", "ev-dinner"]
    assert agent(env, "get_calendar_events_by_tag", tag="gym") == []


def test_agent_reads_are_available_in_observe_mode(env: Environment) -> None:
    result = env.call("assistant", "calendar__search_events", {"query": "yoga"}, mode="observe")
    assert ids(ok(result)) == ["ev-yoga"]
    err(
        env.call("assistant", "calendar__delete_calendar_event", {"event_id": "ev-yoga"}, mode="observe"),
        "execute mode",
    )
    assert "ev-yoga" in events(env)


def test_agent_writes(env: Environment) -> None:
    new_id = agent(
        env,
        "add_calendar_event",
        title="Haircut",
        start_datetime="2025-03-06T17:00:00",
        end_datetime="2025-03-06T17:45:00",
        tag="personal",
        location="Barber Joe's",
        attendees=["Joe"],
    )["id"]
    stored = events(env)[new_id]
    assert stored["start_datetime"] == "2025-03-06T17:00:00Z"
    assert (stored["tag"], stored["location"], stored["attendees"]) == ("personal", "Barber Joe's", ["Joe"])
    assert stored["description"] is None
    assert "personal" in agent(env, "get_all_tags")

    moved = agent(
        env,
        "edit_calendar_event",
        event_id=new_id,
        updates={"start_datetime": "2025-03-06 18:00", "end_datetime": "2025-03-06 18:45", "tag": None},
    )
    assert (moved["start_datetime"], moved["end_datetime"]) == (
        "2025-03-06T18:00:00Z",
        "2025-03-06T18:45:00Z",
    )
    assert moved["tag"] is None
    assert moved["location"] == "Barber Joe's"
    assert events(env)[new_id] == moved
    # changing only the end is fine while it stays after the start
    assert (
        agent(env, "edit_calendar_event", event_id=new_id, updates={"end_datetime": "2025-03-06 19:00"})[
            "end_datetime"
        ]
        == "2025-03-06T19:00:00Z"
    )
    assert agent(env, "edit_calendar_event", event_id=new_id, updates={"attendees": ["Joe", "Dana Park"]})[
        "attendees"
    ] == ["Joe", "Dana Park"]

    assert new_id in agent(env, "delete_calendar_event", event_id=new_id)
    assert new_id not in events(env)


def test_new_ids_do_not_collide(env: Environment) -> None:
    first = agent(
        env,
        "add_calendar_event",
        title="A",
        start_datetime="2025-03-10 09:00",
        end_datetime="2025-03-10 10:00",
    )["id"]
    second = agent(
        env,
        "add_calendar_event",
        title="B",
        start_datetime="2025-03-10 09:00",
        end_datetime="2025-03-10 10:00",
    )["id"]
    assert first != second
    assert {first, second} <= set(events(env))


@pytest.mark.parametrize(
    ("tool", "args", "message"),
    [
        ("get_calendar_event", {"event_id": "ghost"}, "no event with id 'ghost'"),
        (
            "get_calendar_events_from_to",
            {"start_datetime": "2025-03-05 00:00", "end_datetime": "2025-03-04 00:00"},
            "must be after the start",
        ),
        (
            "get_calendar_events_from_to",
            {"start_datetime": "2025-03-04 00:00", "end_datetime": "2025-03-05 00:00", "limit": 0},
            "limit",
        ),
        (
            "get_calendar_events_from_to",
            {"start_datetime": "2025-03-04 00:00", "end_datetime": "2025-03-05 00:00", "offset": -1},
            "offset",
        ),
        (
            "get_calendar_events_from_to",
            {"start_datetime": "tomorrow", "end_datetime": "2025-03-05 00:00"},
            "start_datetime",
        ),
        ("search_events", {"query": "  "}, "empty"),
        ("get_calendar_events_by_tag", {"tag": " "}, "empty"),
        (
            "add_calendar_event",
            {"title": " ", "start_datetime": "2025-03-04 10:00", "end_datetime": "2025-03-04 11:00"},
            "needs a title",
        ),
        (
            "add_calendar_event",
            {"title": "Backwards", "start_datetime": "2025-03-04 10:00", "end_datetime": "2025-03-04 09:00"},
            "must be after the start",
        ),
        (
            "add_calendar_event",
            {"title": "Empty", "start_datetime": "2025-03-04 10:00", "end_datetime": "2025-03-04 10:00"},
            "must be after the start",
        ),
        ("add_calendar_event", {"title": "No end", "start_datetime": "2025-03-04 10:00"}, "end_datetime"),
        ("edit_calendar_event", {"event_id": "ghost", "updates": {"title": "x"}}, "ghost"),
        ("edit_calendar_event", {"event_id": "ev-yoga", "updates": {}}, "no field"),
        ("edit_calendar_event", {"event_id": "ev-yoga", "updates": {"title": " "}}, "cannot be empty"),
        ("edit_calendar_event", {"event_id": "ev-yoga", "updates": {"title": None}}, "cannot be removed"),
        (
            "edit_calendar_event",
            {"event_id": "ev-yoga", "updates": {"start_datetime": None}},
            "cannot be removed",
        ),
        (
            "edit_calendar_event",
            {"event_id": "ev-yoga", "updates": {"start_datetime": "2025-03-06 20:00"}},
            "give both start_datetime and end_datetime",
        ),
        (
            "edit_calendar_event",
            {
                "event_id": "ev-yoga",
                "updates": {"start_datetime": "2025-03-07 18:00", "end_datetime": "2025-03-07 17:00"},
            },
            "before it starts",
        ),
        ("edit_calendar_event", {"event_id": "ev-yoga", "updates": {"colour": "red"}}, "updates.colour"),
        ("delete_calendar_event", {"event_id": "ghost"}, "ghost"),
    ],
)
def test_agent_api_errors_change_nothing(env: Environment, tool: str, args: dict, message: str) -> None:
    before = env.snapshot()
    err(env.call("assistant", f"calendar__{tool}", args, mode="execute"), message)
    assert env.snapshot() == before


def test_the_assistant_cannot_act_as_an_attendee(env: Environment) -> None:
    before = env.snapshot()
    err(
        env.call(
            "assistant",
            "calendar__delete_calendar_event_by_attendee",
            {"who_delete": "Alice Chen", "event_id": "ev-review"},
            mode="execute",
        )
    )
    assert env.snapshot() == before


# -- the world -------------------------------------------------------------------------------------

PARTY = {
    "who_add": "Dana Park",
    "title": "Dana's birthday party",
    "start_datetime": "2025-03-07T18:00:00",
    "end_datetime": "2025-03-07T20:00:00",
    "tag": "social",
    "location": "The rooftop bar on the corner of Fifth Avenue and Main Street, top floor",
    "attendees": ["Alice Chen"],
    "event_id": "ev-party",
}


def test_attendee_adds_an_event(env: Environment) -> None:
    env.user_view()  # read what came before
    env.assistant_observation()
    assert ok(env.call("env", "calendar__add_calendar_event_by_attendee", PARTY)) == "ev-party"
    stored = events(env)["ev-party"]
    assert stored["title"] == "Dana's birthday party"
    assert stored["attendees"] == ["Dana Park", "Alice Chen"]
    assert stored["start_datetime"] == "2025-03-07T18:00:00Z"

    user = env.user_view().notifications
    assert len(user) == 1
    assert "Calendar: Dana Park added an event — Dana's birthday party" in user[0]
    assert "Fri 2025-03-07 18:00-20:00 at The rooftop bar" in user[0]
    assert user[0].endswith("…")  # truncated like a phone notification
    assert "top floor" not in user[0] and "ev-party" not in user[0]

    assistant = env.assistant_observation().notifications
    assert len(assistant) == 1
    assert "Dana Park added an event" in assistant[0]
    assert "Main Street, top floor" in assistant[0]
    assert "event_id=ev-party" in assistant[0]
    notification = env.notifications.inboxes["assistant"].items[-1]
    assert (notification.kind, notification.data) == ("event_added", {"event_id": "ev-party"})

    # the user finds it on the agenda
    ok(env.call("user", "set_day", {"day": "2025-03-07"}))
    assert ids(ok(env.call("user", "list_events"))["events"]) == ["ev-party", "ev-dinner"]


def test_attendee_adds_an_event_with_a_new_id(env: Environment) -> None:
    args = {k: v for k, v in PARTY.items() if k not in ("event_id", "attendees", "location")}
    new_id = ok(env.call("env", "calendar__add_calendar_event_by_attendee", args))
    assert events(env)[new_id]["attendees"] == ["Dana Park"]
    assistant = env.assistant_observation().notifications
    assert assistant[-1].endswith(f"Fri 2025-03-07 18:00-20:00\n(event_id={new_id})")


@pytest.mark.parametrize(
    ("changes", "message"),
    [
        ({"event_id": "ev-yoga"}, "already exists"),
        ({"who_add": " "}, "who_add"),
        ({"title": ""}, "needs a title"),
        ({"end_datetime": "2025-03-07T17:00:00"}, "must be after the start"),
    ],
)
def test_attendee_add_errors_change_nothing(env: Environment, changes: dict, message: str) -> None:
    before = env.snapshot()
    err(env.call("env", "calendar__add_calendar_event_by_attendee", {**PARTY, **changes}), message)
    assert env.snapshot() == before
    assert env.user_view().notifications == []
    assert env.assistant_observation().notifications == []


def test_attendee_removes_an_event(env: Environment) -> None:
    result = ok(
        env.call(
            "env",
            "calendar__delete_calendar_event_by_attendee",
            {"who_delete": "alice chen", "event_id": "ev-review"},
        )
    )
    assert "ev-review" in result
    assert "ev-review" not in events(env)

    user = env.user_view().notifications
    assert len(user) == 1
    assert (
        "Calendar: Alice Chen removed an event — Quarterly review: Wed 2025-03-05 15:00-16:30 at Board room"
        in user[0]
    )
    assert "ev-review" not in user[0]
    assistant = env.assistant_observation().notifications
    assert "event_id=ev-review" in assistant[-1]
    assert env.notifications.inboxes["assistant"].items[-1].kind == "event_removed"


@pytest.mark.parametrize(
    ("args", "message"),
    [
        ({"who_delete": "Alice Chen", "event_id": "ghost"}, "no event with id 'ghost'"),
        (
            {"who_delete": "Mallory", "event_id": "ev-review"},
            "'mallory' is not an attendee of event ev-review; its attendees are alice chen",
        ),
        ({"who_delete": "Alice Chen", "event_id": "ev-yoga"}, "its attendees are none"),
    ],
)
def test_attendee_remove_errors_change_nothing(env: Environment, args: dict, message: str) -> None:
    before = env.snapshot()
    err(env.call("env", "calendar__delete_calendar_event_by_attendee", args), message)
    assert env.snapshot() == before
    assert env.assistant_observation().notifications == []


def test_an_open_detail_of_a_cancelled_event(env: Environment) -> None:
    ok(env.call("user", "open_event", {"event_id": "ev-team-lunch"}))
    ok(
        env.call(
            "env",
            "calendar__delete_calendar_event_by_attendee",
            {"who_delete": "Dana Park", "event_id": "ev-team-lunch"},
        )
    )
    err(env.call("user", "refresh"), "no event with id 'ev-team-lunch'")
    ok(env.call("user", "go_back"))
    assert "ev-team-lunch" not in ids(ok(env.call("user", "set_day", {"day": "2025-03-05"}))["events"])


def test_adding_an_event_says_what_was_added_and_when(env: Environment) -> None:
    added = agent(
        env,
        "add_calendar_event",
        title="Haircut",
        start_datetime="2025-03-06 17:00",
        end_datetime="2025-03-06 17:45",
        location="Barber Joe's",
        attendees=["Joe", "Ana"],
    )
    assert added["done"] == (
        f"Added event {added['id']} 'Haircut' to the calendar: Thu 2025-03-06 17:00-17:45 at Barber Joe's "
        "with Joe and Ana."
    )
    assert events(env)[added["id"]]["title"] == "Haircut"
