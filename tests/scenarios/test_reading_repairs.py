"""Readings a reviewer's probes found wrong, repaired for every scenario: a piece written with a stop and
a space ("no. 14") finds the text without the space, a clause bounding the plan ("before you head off on
Thursday") does not name the plan's day, and a repeating reminder is forbidden when a later occurrence is."""

from __future__ import annotations

from datetime import UTC, datetime
from typing import Any

import pytest

from pare.bench import run_episode
from pare.scenarios import OracleAssistant, OracleUser, Scenario, load_scenarios
from pare.scenarios.meaning import has_word, mentions_day, without_bound
from pare.scenarios.model import OracleAction, Solution
from pare.scenarios.occurrences import ENDLESS, occurrence_records

MONDAY = datetime(2025, 9, 8, 10, 15, tzinfo=UTC)
THURSDAY = MONDAY.date().replace(day=11)


@pytest.mark.parametrize(
    ("text", "found"),
    [
        ("Pop round to no.14 for your birthday present", True),
        ("Collect it from no. 14", True),
        ("no.  14, the blue door", True),
        ("no.140", False),
        ("no14", False),
    ],
)
def test_a_space_after_a_stop_may_be_left_out(text: str, found: bool) -> None:
    assert has_word(text, "no. 14") is found


def test_a_space_between_words_is_still_needed() -> None:
    assert has_word("dry cleaning", "dry clean*") and not has_word("drycleaning", "dry clean*")


@pytest.mark.parametrize(
    ("text", "names_thursday"),
    [
        ("Thank you! I'll pop round for it before you head off on Thursday.", False),
        ("I'll come by until she flies on Thursday", False),
        ("I'll come round on Thursday before work", True),
        ("Thursday before 10 works for me", True),
        ("I'll come on Thursday, before you're up", True),
    ],
)
def test_a_clause_of_someone_elses_act_bounds_the_plan(text: str, names_thursday: bool) -> None:
    assert mentions_day(text, THURSDAY, MONDAY) is names_thursday


def test_the_bound_is_cut_from_the_clause_only_where_a_subject_follows() -> None:
    assert without_bound("I'll pop round before you head off on Thursday") == "I'll pop round "
    assert without_bound("before 10 on Thursday") == "before 10 on Thursday"


def _due(record: dict[str, Any]) -> list[str]:
    return [view["due_datetime"] for view in occurrence_records(record)]


def test_a_repeating_reminder_is_read_as_its_next_following_and_last_occurrence() -> None:
    once = {"due_datetime": "2025-09-09T18:30:00+00:00", "repetition": "none"}
    assert occurrence_records(once) == (once,)
    endless = {**once, "repetition": "daily"}
    assert _due(endless) == [
        "2025-09-09T18:30:00+00:00",
        "2025-09-10T18:30:00+00:00",
        (datetime(2025, 9, 9, 18, 30, tzinfo=UTC) + ENDLESS).isoformat(),
    ]
    until_wednesday = {**endless, "repeat_until": "2025-09-10T20:00:00+00:00"}
    assert _due(until_wednesday) == ["2025-09-09T18:30:00+00:00", "2025-09-10T18:30:00+00:00"]
    weekly_to_the_third = {**once, "repetition": "weekly", "repeat_until": "2025-09-30T00:00:00+00:00"}
    assert _due(weekly_to_the_third)[-1] == "2025-09-23T18:30:00+00:00"


NEIGHBOUR: Scenario = next(s for s in load_scenarios() if s.id == "neighbour_parcel_held_pickup_reminder")


def _remind(**args: Any) -> Solution:
    """The oracle's solution with its reminder set as ``args`` say."""
    oracle = NEIGHBOUR.solution()
    last = oracle.interventions[-1]
    actions = [
        OracleAction.model_validate(
            {"tool": "reminder__add_reminder", "args": {"title": "Collect parcel from Rosa", **args}}
        )
    ]
    changed = last.model_copy(update={"actions": actions})
    return Solution("probe", oracle.user, (*oracle.interventions[:-1], changed))


def _goal_met(solution: Solution) -> bool:
    result = run_episode(NEIGHBOUR, OracleUser(NEIGHBOUR, solution), OracleAssistant(NEIGHBOUR, solution))
    return next(goal.passed for goal in result.outcome.goals if goal.id == "reminder_set")


def test_a_check_that_forbids_due_times_reads_every_occurrence() -> None:
    assert _goal_met(_remind(due_datetime="day+1 18:30"))
    assert not _goal_met(_remind(due_datetime="day+1 18:30", repetition="daily"))  # rings on after Thursday
    assert _goal_met(_remind(due_datetime="day+1 18:30", repetition="daily", repeat_until="day+2 20:00"))
