"""A check that raises fails, saying what it raised; the episode and the other checks are kept."""

from __future__ import annotations

import asyncio
from collections.abc import Iterator, Sequence
from datetime import datetime
from typing import Any

import pytest

from pare.bench import run_episode
from pare.errors import ModelRequestError
from pare.scenarios import OracleAssistant, OracleUser
from pare.scenarios.checks import JudgeVerdict, aevaluate, goals_met
from pare.scenarios.matchers import Operator, register_operator, unregister_operator
from tests.scenarios.helpers import base, parse


def _breaks(expected: Any, value: Any, start: datetime) -> bool:
    raise ZeroDivisionError("a test that divides by zero")


@pytest.fixture
def breaks() -> Iterator[None]:
    register_operator(Operator("breaks", "true", "raises whatever it is given", _breaks))
    try:
        yield
    finally:
        unregister_operator("breaks")


def _scenario_with(*checks: dict[str, Any]) -> Any:
    data = base()
    data["goals"].append({"id": "more", "description": "more checks", "checks": list(checks)})
    return parse(data)


REPLIED = {"action": {"tool": "email__reply_to_email", "args": {"email_id": "e_ann"}}}
JUDGED = {
    "judge": {
        "action": {"tool": "email__reply_to_email"},
        "criterion": "Says Thursday works.",
        "fallback": {"affirms": "thursday"},
    }
}


def test_a_check_that_raises_fails_with_its_exception_and_the_episode_is_kept(breaks: None) -> None:
    exploding = {"action": {"tool": "email__reply_to_email", "args": {"content": {"breaks": True}}}}
    scenario = _scenario_with(REPLIED, exploding)
    result = run_episode(scenario, OracleUser(scenario), OracleAssistant(scenario))
    assert not result.success
    (replied, more) = result.outcome.goals
    assert replied.passed  # the other goal is judged as ever
    met, raised = more.checks
    assert met.passed and not raised.passed
    assert raised.form == "action"
    assert raised.detail == "the check raised ZeroDivisionError: a test that divides by zero"
    assert not raised.user_made  # asked again crediting the user, it raises again: not the user's work
    assert not goals_met(scenario, result.env.log.entries, result.env.snapshot())


def _judge_raising(error: Exception) -> Any:
    async def judge(criterion: str, text: str, facts: Sequence[str] = ()) -> JudgeVerdict:
        raise error

    return judge


def test_a_judge_that_raises_fails_its_check() -> None:
    scenario = _scenario_with(JUDGED)
    result = run_episode(scenario, OracleUser(scenario), OracleAssistant(scenario))
    outcome = asyncio.run(
        aevaluate(
            scenario, result.env.log.entries, result.env.snapshot(), judge=_judge_raising(KeyError("verdict"))
        )
    )
    (judged,) = outcome.goals[1].checks
    assert not judged.passed and judged.detail == "the check raised KeyError: 'verdict'"
    assert outcome.goals[0].passed


def test_a_model_providers_refusal_is_not_a_verdict() -> None:
    scenario = _scenario_with(JUDGED)
    result = run_episode(scenario, OracleUser(scenario), OracleAssistant(scenario))
    refused = ModelRequestError("the judge's key was refused", kind="authentication")
    with pytest.raises(ModelRequestError):
        asyncio.run(
            aevaluate(scenario, result.env.log.entries, result.env.snapshot(), judge=_judge_raising(refused))
        )
