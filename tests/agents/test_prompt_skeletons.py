"""The system prompts are rendered once per phone and settings as skeletons with holes for the values of
one episode (start time, persona and goal, the task): filled in, each must be exactly what rendering its
template with every value gives.
"""

from __future__ import annotations

from datetime import UTC, datetime
from typing import Any

import pytest

from pare.agents import prompts
from pare.agents.policy import ASSISTANT_WAIT, SEND_MESSAGE, Task
from pare.agents.prompts import execute_system_prompt, observe_system_prompt, user_system_prompt
from pare.env import EnvConfig, Environment
from pare.errors import SimulationBug
from pare.sim.budget import DEFAULT_BUDGET, TurnBudget

# values that could trip a filling-in: markup, a hole's own marker, whitespace at the edges
AWKWARD = "  {{ goal }} {% if x %}\x00hole:goal\x00 \n"
BUDGETS = (
    DEFAULT_BUDGET,
    TurnBudget(max_turns=4, user_steps=2, proposal_ttl_turns=1),
    TurnBudget(proposal_ttl_turns=None, user_prompt="paper"),  # the paper protocol: its wording, no expiry
)


def _direct(role: str, env: Environment, native_tools: bool, **context: Any) -> str:
    """The role's template rendered with every value, as prompts were before skeletons."""
    context.update(apps=prompts._apps(env), example=prompts.example_for(env, role), native_tools=native_tools)
    text: str = prompts._templates().get_template(f"{role}.j2").render(**context)
    return text.strip() + "\n"


def _env(apps: list[str], hour: int) -> Environment:
    return Environment(apps, EnvConfig(start_time=datetime(2025, 3, 3, hour, 30, tzinfo=UTC)))


PHONES = (["email", "calendar"], ["calendar"], ["shopping", "messaging", "contacts"])


@pytest.mark.parametrize("native_tools", [False, True])
@pytest.mark.parametrize("budget", BUDGETS)
@pytest.mark.parametrize("apps", PHONES)
def test_user_prompts_are_the_templates_rendered(
    apps: list[str], budget: TurnBudget, native_tools: bool
) -> None:
    for hour in (9, 17):
        env = _env(apps, hour)
        for persona in (None, "", "A nurse on night shifts.", AWKWARD):
            for goal in (None, "", "Book a cab to the airport.", AWKWARD):
                prompt = user_system_prompt(
                    env, persona=persona, goal=goal, native_tools=native_tools, budget=budget
                )
                assert prompt == _direct(
                    "user",
                    env,
                    native_tools,
                    start=prompts._start(env),
                    budget=budget,
                    notification_policy=prompts._user_notifications(env, budget),
                    persona=persona,
                    goal=goal,
                )


@pytest.mark.parametrize("native_tools", [False, True])
@pytest.mark.parametrize("apps", PHONES)
def test_assistant_prompts_are_the_templates_rendered(apps: list[str], native_tools: bool) -> None:
    for hour in (9, 17):
        env = _env(apps, hour)
        lists = prompts._assistant_tool_lists(env)
        for budget in BUDGETS:
            assert observe_system_prompt(env, native_tools=native_tools, budget=budget) == _direct(
                "observe",
                env,
                native_tools,
                start=prompts._start(env),
                budget=budget,
                notification_policy=prompts._assistant_notifications(env),
                propose_tool=SEND_MESSAGE,
                wait_tool=ASSISTANT_WAIT,
                tools=lists.observe,
                execute_tools=lists.execute_only,
            )
        for proposal in ("Reply to Ann.", "", AWKWARD):
            for answer in ("", "Yes, and cc Bob.", AWKWARD):
                for max_steps in (3, 10):
                    task = Task(proposal, answer, "proposal-1")
                    prompt = execute_system_prompt(env, task, max_steps=max_steps, native_tools=native_tools)
                    assert prompt == _direct(
                        "execute",
                        env,
                        native_tools,
                        now=prompts._now(env),
                        proposal=proposal,
                        answer=answer,
                        report_tool=SEND_MESSAGE,
                        max_steps=max_steps,
                        tools=lists.execute,
                    )


def test_a_value_at_the_edge_of_a_prompt_is_refused() -> None:
    # the prompt is stripped as a whole: a value at its edge would lose its own whitespace
    with pytest.raises(SimulationBug):
        prompts._Skeleton.of("\x00hole:goal\x00 and the rest")
    with pytest.raises(SimulationBug):
        prompts._Skeleton.of("the start, then \x00hole:goal\x00\n")
    assert prompts._Skeleton.of("a \x00hole:goal\x00 b").fill({"goal": " x "}) == "a  x  b\n"


def test_each_phone_s_prompts_list_its_own_apps() -> None:
    # the app lines are made once per set of apps, and the skeletons are keyed by them
    for apps in (*PHONES, ["calendar", "email"]):
        env = _env(apps, 9)
        shown = ["files", *apps]  # the core apps first; of those only Files is listed
        listed = user_system_prompt(env).split("## Your phone\n")[1].split("\n- On the home screen")[0]
        assert [line.split(":")[0] for line in listed.splitlines()] == [f"- {app}" for app in shown]
        execute = execute_system_prompt(env, Task("Do it.", "", "proposal-1"), max_steps=10)
        assert f"Apps on this phone: {', '.join(shown)}." in execute
