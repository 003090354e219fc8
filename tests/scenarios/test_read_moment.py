"""A reminder's text is read as of when it is written and as of when it fires."""

from __future__ import annotations

from datetime import UTC, datetime
from typing import Any

from pare.bench import run_episode
from pare.scenarios import OracleAssistant, OracleUser, evaluate
from pare.scenarios.read_moment import due_moment, fires_at
from pare.sim.log import LogEntry
from tests.scenarios.helpers import base, parse

WRITTEN = datetime(2025, 3, 3, 9, 0, tzinfo=UTC)  # a Monday


def _entry(app: str, args: dict[str, Any]) -> LogEntry:
    return LogEntry(4, 1, WRITTEN, "assistant", app, "add_reminder", args, "write", True)


def test_a_reminder_fires_at_its_due_time_and_other_texts_are_read_when_sent() -> None:
    saturday = datetime(2025, 3, 8, 10, 0, tzinfo=UTC)
    assert fires_at(_entry("reminder", {"title": "t", "due_datetime": "2025-03-08T10:00:00Z"})) == saturday
    assert fires_at(_entry("email", {"due_datetime": "2025-03-08T10:00:00Z"})) is None
    assert due_moment({"updates": {"due_datetime": "2025-03-08T10:00:00Z"}}, WRITTEN) == saturday
    assert due_moment({"due_datetime": "2025-03-01T10:00:00Z"}, WRITTEN) is None  # due before it was written


def test_a_state_check_gives_the_benefit_of_the_doubt_between_the_two_readings() -> None:
    data = base()
    data["apps"] = ["email", "calendar", "reminder"]
    reminder = {
        "tool": "reminder__add_reminder",
        "args": {"title": "Enter the race", "due_datetime": "day+5 10:00",
                 "description": "Entries close tomorrow, Sunday."},
    }  # fmt: skip
    data["oracle"]["interventions"][0]["actions"].append(reminder)
    sunday = {"description": {"only_days": ["day+6"], "mentions_day": "day+6"}}
    data["goals"].append(
        {
            "id": "reminded",
            "description": "A reminder on Saturday says entries close on Sunday.",
            "checks": [
                {"state": {"path": "reminder.reminders", "where": sunday, "count": 1}},
                # read as of Monday, "tomorrow" is Tuesday: an unwanted day only if it is in both readings
                {"state": {"path": "reminder.reminders", "where": {"description": {"mentions_day": "day+1"}},
                           "count": 0}},
            ],
        }
    )  # fmt: skip
    scenario = parse(data)
    result = run_episode(scenario, OracleUser(scenario), OracleAssistant(scenario))
    outcome = evaluate(
        scenario, result.env.log.entries, result.env.snapshot(), attribution=result.env.attribution
    )
    assert outcome.success, [failure.detail for failure in outcome.failures()]
