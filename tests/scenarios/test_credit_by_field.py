"""Who made an item is read from the fields a check reads: the assistant is credited with what it wrote,
not with the item it touched last."""

from __future__ import annotations

from typing import Any

from pare.bench import run_episode
from pare.env.attribution import Attribution
from pare.scenarios import OracleAssistant, OracleUser, evaluate
from pare.scenarios.checks import CheckResult
from tests.scenarios.helpers import base, parse

DENTIST = {"title": {"contains": "dentist"}, "start_datetime": "day+2 10:00"}
"""The goal: the dentist on Wednesday 5 March at 10:00 (the tiny scenario starts on Monday 3 March)."""

BY_THE_ASSISTANT = {"state": {"path": "calendar.events", "by": "assistant", "where": DENTIST, "count": 1}}

USER_ADDS_IT = [
    {"tool": "open_app", "args": {"app_name": "calendar"}},
    {"tool": "start_create_event"},
    {"tool": "set_title", "args": {"title": "Dentist"}},
    {"tool": "set_time_range", "args": {"start_datetime": "day+2 10:00", "end_datetime": "day+2 10:30"}},
    {"tool": "save"},
]

FOUND = {"id": "found", "tool": "calendar__search_events", "args": {"query": "Dentist"}}


def _scenario(user_steps: list[dict[str, Any]], actions: list[dict[str, Any]]) -> Any:
    data = base()
    data["oracle"]["user"] = user_steps
    intervention: dict[str, Any] = {
        "proposal": "Shall I see to the dentist on Wednesday?",
        "actions": actions,
    }
    if user_steps:
        intervention["when"] = {"action": {"actor": "user", "tool": "calendar__save"}}
    data["oracle"]["interventions"] = [intervention]
    data["goals"] = [{"id": "dentist", "description": "The dentist is booked.", "checks": [BY_THE_ASSISTANT]}]
    return parse({key: value for key, value in data.items() if key != "events"} | {"events": []})


def _check(user_steps: list[dict[str, Any]], actions: list[dict[str, Any]]) -> CheckResult:
    scenario = _scenario(user_steps, actions)
    result = run_episode(scenario, OracleUser(scenario), OracleAssistant(scenario))
    assert all(entry.ok for entry in result.env.log if entry.actor != "env"), "every call succeeds"
    return result.outcome.goals[0].checks[0]


def test_a_note_on_the_users_own_event_is_not_the_assistants_work() -> None:
    note = {
        "tool": "calendar__edit_calendar_event",
        "args": {"event_id": "${found.0.event_id}", "updates": {"description": "Bring the referral letter."}},
    }
    check = _check(USER_ADDS_IT, [FOUND, note])
    assert not check.passed and check.user_made
    assert "0 of them made by the assistant (1 more only changed by it)" in check.detail


def test_the_event_the_assistant_adds_is_its_work() -> None:
    add = {
        "tool": "calendar__add_calendar_event",
        "args": {"title": "Dentist", "start_datetime": "day+2 10:00", "end_datetime": "day+2 10:30"},
    }
    check = _check([], [add])
    assert check.passed and "1 of them made by the assistant" in check.detail


def test_moving_the_users_event_to_the_right_time_is_the_assistants_work() -> None:
    """Mixed: the user wrote the title, the assistant the time the check needs."""
    early = [
        *USER_ADDS_IT[:3],
        {**USER_ADDS_IT[3], "args": {"start_datetime": "day+2 08:00", "end_datetime": "day+2 08:30"}},
        USER_ADDS_IT[4],
    ]
    move = {
        "tool": "calendar__edit_calendar_event",
        "args": {
            "event_id": "${found.0.event_id}",
            "updates": {"start_datetime": "day+2 10:00", "end_datetime": "day+2 10:30"},
        },
    }
    assert _check(early, [FOUND, move]).passed


# -- the same rules on a state and marks written by hand ---------------------------------------------------
EVENT = {"event_id": "ev-d", "title": "Dentist", "start_datetime": "2025-03-05T10:00:00Z", "description": ""}


def _state(**fields: Any) -> dict[str, Any]:
    return {"calendar": {"events": {"ev-d": {**EVENT, **fields}}}, "email": {"emails": {}}}


def _verdict(check: dict[str, Any], marks: Attribution, state: dict[str, Any]) -> CheckResult:
    data = base()
    replied = {"action": {"tool": "email__reply_to_email"}}  # a positive check on the assistant's work
    data["goals"] = [{"id": "g", "description": "goal", "checks": [replied, check]}]
    return evaluate(parse(data), [], state, attribution=marks).goals[0].checks[1]


def _user_made_it() -> Attribution:
    marks = Attribution()
    marks.record("user", 3, "calendar", {"events": {}}, {"events": {"ev-d": EVENT}})
    return marks


def test_a_value_the_check_reads_through_any_of_counts_only_where_it_is_needed() -> None:
    either = {"any_of": [{"title": {"contains": "dentist"}}, {"description": {"contains": "dentist"}}]}
    check = {"state": {"path": "calendar.events", "by": "assistant", "where": either}}
    marks = _user_made_it()
    noted = _state(description="Dentist: bring the letter.")
    marks.record("assistant", 7, "calendar", _state()["calendar"], noted["calendar"])
    assert not _verdict(check, marks, noted).passed  # the user's title holds without the note
    retitled = _state(title="Check-up", description="Dentist: bring the letter.")
    marks = _user_made_it()
    marks.record("user", 5, "calendar", _state()["calendar"], _state(title="Check-up")["calendar"])
    marks.record("assistant", 7, "calendar", _state(title="Check-up")["calendar"], retitled["calendar"])
    assert _verdict(check, marks, retitled).passed  # only the assistant's description says dentist


def test_a_limit_counts_every_item_the_assistant_had_a_hand_in() -> None:
    never = {
        "state": {"path": "calendar.events", "by": "assistant", "where": {"title": "Dentist"}, "count": 0}
    }
    marks = _user_made_it()
    noted = _state(description="Moved by the assistant.")
    marks.record("assistant", 7, "calendar", _state()["calendar"], noted["calendar"])
    marks.record("user", 9, "calendar", noted["calendar"], _state(description="Mine again.")["calendar"])
    failed = _verdict(never, marks, _state(description="Mine again."))
    assert (
        not failed.passed and "0 of them made by the assistant (1 more only changed by it)" in failed.detail
    )
    assert _verdict(never, _user_made_it(), _state()).passed


def test_a_value_check_reads_who_last_set_that_value() -> None:
    start = {
        "state": {
            "path": "calendar.events.ev-d.start_datetime",
            "by": "assistant",
            "value": {"present": True},
        }
    }
    marks = _user_made_it()
    noted = _state(description="Bring the letter.")
    marks.record("assistant", 7, "calendar", _state()["calendar"], noted["calendar"])
    assert not _verdict(start, marks, noted).passed
    moved = _state(start_datetime="2025-03-05T11:00:00Z", description="Bring the letter.")
    marks.record("assistant", 8, "calendar", noted["calendar"], moved["calendar"])
    assert _verdict(start, marks, moved).passed
