"""The dry run's plan: key status and an estimate measured on the prompts PARE really renders."""

from __future__ import annotations

import asyncio
import math
from collections import Counter

import pytest

from pare.agents.prompts import user_system_prompt
from pare.bench import run_episode
from pare.bench.plan_estimate import (
    CHARS_PER_TOKEN,
    ceiling_calls,
    estimate,
    key_statuses,
    measure_scenario,
    measure_scenarios,
)
from pare.bench.runconfig import RunConfig, build_config
from pare.scenarios import OracleAssistant, OracleUser, build_environment, get_scenario

SCENARIO = "dentist_moves_checkup"
NO_PROPOSAL = "abandoned_cart_left_on_purpose_needs_nothing"


def model_config(**models: object) -> RunConfig:
    return build_config({"models": models, "scenarios": {"ids": [SCENARIO]}})


CONFIG = model_config(user={"model": "u", "prices": {"input": 1, "output": 1}}, assistant={"model": "a"})


def oracle_calls(config: RunConfig, scenario_id: str) -> tuple[Counter[str], int]:
    """Per role, the steps the oracle takes in one episode (a model on its path makes one call each)."""
    scenario = get_scenario(scenario_id)
    result = run_episode(
        scenario,
        OracleUser(scenario),
        OracleAssistant(scenario),
        config.episode_settings(config.episode_seed(scenario_id, 1)),
    )
    return Counter(step.mode or step.actor for step in result.steps), result.turns


@pytest.mark.parametrize("scenario_id", [SCENARIO, NO_PROPOSAL])
def test_typical_calls_follow_the_oracles_path(scenario_id: str) -> None:
    steps, turns = oracle_calls(CONFIG, scenario_id)
    shape = measure_scenarios(CONFIG, {scenario_id: get_scenario(scenario_id)})[scenario_id]
    assert shape.turns == turns
    result = estimate(CONFIG, {scenario_id: shape}, {scenario_id: 3})
    roles = {role.role: role for role in result.roles}
    for role in ("user", "observe", "execute"):
        assert roles[role].calls.typical == 3 * steps[role], role
    # the upper bound: max_turns turns at the oracle's pace, and every task (at least one) uses its budget
    assert roles["user"].calls.upper == 3 * math.ceil(steps["user"] * 10 / turns)
    assert roles["observe"].calls.upper == 3 * math.ceil(steps["observe"] * 10 / turns)
    assert roles["execute"].calls.upper == 3 * 10  # one task of execute_steps, even with no proposal
    assert result.mean_turns == turns and result.max_turns == 10
    assert result.episodes == 3


def test_prompts_are_the_rendered_ones_and_grow() -> None:
    scenario = get_scenario(SCENARIO)
    shape = asyncio.run(measure_scenario(scenario, CONFIG, CONFIG.episode_seed(SCENARIO, 1)))
    env = build_environment(scenario, CONFIG.episode_settings(CONFIG.episode_seed(SCENARIO, 1)).env)
    system = user_system_prompt(
        env,
        persona=scenario.user.persona,
        goal=scenario.user.goal,
        budget=CONFIG.episode_settings(0).budget(),
    )
    first = shape.prompts["user"][0]
    assert len(system) < first[0] < len(system) + 4_000  # the system prompt and the first screen
    assert first == sorted(first) and first[-1] > first[0]  # the conversation only grows
    result = estimate(CONFIG, {SCENARIO: shape}, {SCENARIO: 1})
    user = next(role for role in result.roles if role.role == "user")
    assert user.prompt_tokens.typical == pytest.approx(sum(first) / CHARS_PER_TOKEN)
    assert user.cost_usd is not None and user.cost_usd.typical == pytest.approx(
        (round(user.prompt_tokens.typical) + round(user.completion_tokens.typical)) / 1e6
    )


def test_native_tools_count_the_tool_schemas_sent() -> None:
    scenario = {SCENARIO: get_scenario(SCENARIO)}
    text = measure_scenarios(CONFIG, scenario)[SCENARIO]
    native = model_config(user={"model": "u"}, assistant={"model": "a", "native_tools": True})
    schemas = measure_scenarios(native, scenario)[SCENARIO]
    assert sum(map(sum, schemas.prompts["observe"])) > sum(map(sum, text.prompts["observe"]))


def test_finished_episodes_are_not_estimated() -> None:
    shapes = measure_scenarios(CONFIG, {SCENARIO: get_scenario(SCENARIO)})
    nothing = estimate(CONFIG, shapes, {SCENARIO: 0})
    assert nothing.episodes == 0 and nothing.calls.typical == 0 and nothing.calls.upper == 0


def test_the_ceiling_counts_every_step_of_every_turn() -> None:
    config = build_config(
        {
            "models": {"user": {"model": "u"}, "assistant": {"model": "a"}},
            "protocol": {"max_turns": 6, "user_steps": 2, "observe_steps": 3, "execute_steps": 7},
        }
    )
    assert ceiling_calls(config) == 6 * (2 + 7)
    assistant_only = build_config({"models": {"assistant": {"model": "a"}}, "protocol": {"max_turns": 6}})
    assert ceiling_calls(assistant_only) == 6 * 10


def test_key_status_names_the_variable_and_never_its_value() -> None:
    config = build_config(
        {
            "models": {
                "user": {"model": "local", "api_base": "http://localhost:8000/v1", "api_key_env": None},
                "assistant": {"model": "a", "api_key_env": "MY_KEY"},
                "judge": {"model": "j", "api_key_env": "JUDGE_KEY"},
            }
        }
    )
    statuses = {
        status.variable: status for status in key_statuses(config, {"MY_KEY": "sk-x", "JUDGE_KEY": "  "})
    }
    assert statuses["MY_KEY"].found is True and statuses["MY_KEY"].roles == ("observe", "execute")
    assert statuses["JUDGE_KEY"].found is False  # blank is not a key
    assert statuses[None].found is None and statuses[None].roles == ("user",)
    assert "sk-x" not in repr(statuses)


def test_litellm_providers_are_checked_by_litellm(monkeypatch: pytest.MonkeyPatch) -> None:
    pytest.importorskip("litellm")
    monkeypatch.delenv("ANTHROPIC_API_KEY", raising=False)
    config = build_config(
        {"models": {"assistant": {"model": "anthropic/claude-3-5-sonnet-latest", "backend": "litellm"}}}
    )
    statuses = key_statuses(config)
    assert [(s.variable, s.found, s.roles) for s in statuses] == [
        ("ANTHROPIC_API_KEY", False, ("observe", "execute"))
    ]
