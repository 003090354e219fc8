"""A scenario marked end_when_met stops once its verdict cannot change, instead of playing to the limit."""

from __future__ import annotations

from typing import Any

import pytest

from pare.bench import run_episode
from pare.errors import UserInputError
from pare.scenarios import OracleAssistant, OracleUser, Scenario
from tests.scenarios.helpers import base, parse


def _with_late_event(end_when_met: bool) -> Scenario:
    """The tiny reply scenario, with a newsletter two days later that nothing depends on."""
    data: dict[str, Any] = base()
    data["events"].append(
        {
            "id": "newsletter",
            "at": "+2d",
            "tool": "email__receive_email",
            "args": {"sender": "news@x.example", "subject": "Weekly digest", "content": "Our news."},
        }
    )
    if end_when_met:
        data["end_when_met"] = True
    return parse(data)


def _play(scenario: Scenario) -> Any:
    return run_episode(scenario, OracleUser(scenario), OracleAssistant(scenario))


def test_an_episode_whose_goals_are_met_ends_instead_of_waiting_for_a_later_event() -> None:
    plain = _play(_with_late_event(False))
    marked = _play(_with_late_event(True))
    assert plain.success and marked.success
    assert plain.ended == "idle" and plain.turns > marked.turns  # the plain one waited for the newsletter
    assert any(entry.event_id == "newsletter" for entry in plain.env.log)
    assert not any(entry.event_id == "newsletter" for entry in marked.env.log)
    assert marked.ended == "idle"


def test_unmet_goals_keep_a_marked_episode_going() -> None:
    from pare.agents.policy import SilentAssistant

    scenario = _with_late_event(True)
    result = run_episode(scenario, OracleUser(scenario), SilentAssistant())
    assert not result.success
    assert any(entry.event_id == "newsletter" for entry in result.env.log)  # it waited: the goal was open


def test_a_no_proposal_scenario_cannot_end_when_met() -> None:
    data = base()
    data["kind"] = "no_proposal"
    data["end_when_met"] = True
    data["oracle"]["interventions"] = []
    data["goals"] = [
        {
            "id": "quiet",
            "description": "No proposal.",
            "checks": [{"no_action": {"tool": "agent_ui__send_message_to_user", "mode": "observe"}}],
        }
    ]
    with pytest.raises(UserInputError, match="end_when_met would end it before"):
        parse(data)
