"""Invented details in whole episodes: a right solution that writes a wrong time into a reminder passes
every check but fails on the detail, named in the verdict, kept in the trajectory, counted in the record,
and found again when the stored episode is graded again."""

from __future__ import annotations

import asyncio
import json
from typing import Any

from pare.bench import run_episode
from pare.bench.grading import grade
from pare.env import EnvConfig
from pare.results.records import summarize
from pare.results.trajectory import final_state, parse_trajectory, write_trajectory
from pare.scenarios import OracleAssistant, OracleUser, Scenario, build_environment, get_scenario
from pare.scenarios.model import OracleAction, Solution

WARRANTY = "warranty_ends_reminder_from_receipt"
RIGHT = (
    "Aurel Book 14 warranty ends 21 May 2026. Run diagnostics; below 80% health, contact Aurel support "
    "(case 44817) for a free battery."
)


def _with_description(scenario: Scenario, description: str) -> Solution:
    """The oracle's solution with its reminder's description replaced."""
    oracle = scenario.solution()
    interventions = list(oracle.interventions)
    for number, intervention in enumerate(interventions):
        actions = [
            OracleAction.model_validate(
                {**action.model_dump(), "args": {**action.args, "description": description}}
            )
            if action.tool == "reminder__add_reminder"
            else action
            for action in intervention.actions
        ]
        interventions[number] = intervention.model_copy(update={"actions": actions})
    return Solution("probe", oracle.user, tuple(interventions))


def _play(scenario: Scenario, solution: Solution) -> Any:
    return run_episode(scenario, OracleUser(scenario, solution), OracleAssistant(scenario, solution))


def test_a_wrong_time_in_a_reminders_description_fails_the_episode_and_is_named() -> None:
    scenario = get_scenario(WARRANTY)
    result = _play(scenario, _with_description(scenario, RIGHT + " Support lines open at 07:40."))
    outcome = result.outcome
    # before the rule this passed: every goal is met and nothing is changed that no solution changes
    assert all(goal.passed for goal in outcome.goals) and not outcome.side_effects
    assert not outcome.success
    (detail,) = outcome.invented
    sentence = detail.describe()
    assert sentence.startswith(f"#{detail.order} reminder__add_reminder states 07:40 in description")
    assert "which nothing in the scenario gives" in sentence and "open at 07:40" in sentence
    assert outcome.to_dict()["invented"][0]["text"] == sentence
    record = summarize(result.trajectory())
    assert record["success"] is False
    assert (record["side_effects"], record["invented_details"]) == (1, 1)


def test_the_right_details_in_other_words_are_not_invented() -> None:
    scenario = get_scenario(WARRANTY)
    result = _play(
        scenario, _with_description(scenario, "Warranty to 21/05/2026 - check battery (case 44817).")
    )
    assert result.outcome.invented == () and result.success


def test_the_invented_details_survive_the_trajectory_file_and_a_regrade_finds_them_again() -> None:
    scenario = get_scenario(WARRANTY)
    result = _play(scenario, _with_description(scenario, RIGHT + " Support lines open at 07:40."))
    text = write_trajectory(result.trajectory())
    read = parse_trajectory(text)
    assert [record.text for record in read.outcome.invented] == [result.outcome.invented[0].describe()]
    assert read.outcome.invented[0].kind == "time" and read.outcome.invented[0].shown == "07:40"
    begin = build_environment(scenario, EnvConfig()).snapshot()  # rebuilt as pare regrade does
    outcome, _ = asyncio.run(
        grade(scenario, read.log_entries(), begin, final_state(read, begin), read.attribution_state())
    )
    assert [detail.describe() for detail in outcome.invented] == [result.outcome.invented[0].describe()]


def test_an_older_trajectory_without_invented_details_reads_as_none() -> None:
    scenario = get_scenario(WARRANTY)
    data = json.loads(write_trajectory(_play(scenario, scenario.solution()).trajectory()))
    data["outcome"].pop("invented")
    assert parse_trajectory(json.dumps(data)).outcome.invented == []


def test_a_text_claiming_an_act_no_call_did_fails_the_episode_and_is_named() -> None:
    scenario = get_scenario(WARRANTY)
    result = _play(
        scenario, _with_description(scenario, RIGHT + " I've raised a dispute with Aurel already.")
    )
    assert all(goal.passed for goal in result.outcome.goals) and not result.outcome.success
    (claim,) = result.outcome.invented
    assert claim.kind == "act" and claim.against == "no call of the episode"
    sentence = claim.describe()
    assert sentence.startswith(f'#{claim.order} reminder__add_reminder claims "I\'ve raised a dispute"')
    assert "in description, which no call of the episode did" in sentence
