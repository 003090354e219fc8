"""What the models are shown, through the real turn loop: the assistant remembers what it executed, each
actor is told its budget and the proposal's life, prompts do not state a clock that goes stale, tool
descriptions spell out nested arguments and are not repeated every turn, a pending proposal appears once.
"""

from __future__ import annotations

from datetime import timedelta
from typing import Any

import pytest

from pare.agents.llm import LLMAssistant, LLMUser
from pare.agents.models import ModelClient
from pare.agents.policy import DEFAULT_BUDGET, SilentAssistant, Task, TurnBudget
from pare.agents.prompts import execute_system_prompt, observe_system_prompt, user_system_prompt
from pare.agents.scripted import ScriptedModel
from pare.bench import EpisodeSettings, run_episode
from pare.env import Environment
from pare.scenarios.build import build_environment
from tests.agents.models.conftest import BACKENDS
from tests.agents.models.fake_server import FakeChatServer
from tests.agents.test_llm_episode import (
    ASSISTANT_SCRIPT,
    SCENARIO,
    USER_ACCEPTS,
    _config,
    api_key,  # noqa: F401 - the fixture that sets the test key
)
from tests.agents.test_scripted_actors import WAIT_USER


def _play(servers: tuple[FakeChatServer, FakeChatServer], backend: str) -> list[dict[str, Any]]:
    user_server, assistant_server = servers
    user_server.push(*USER_ACCEPTS)
    assistant_server.push(*ASSISTANT_SCRIPT)
    user = LLMUser(ModelClient(_config(user_server, backend), role="user"))
    assistant = LLMAssistant(ModelClient(_config(assistant_server, backend), role="observe"))
    result = run_episode(SCENARIO, user, assistant)
    assert result.success, result.outcome.failures()
    return assistant_server.requests


@pytest.mark.parametrize("backend", BACKENDS)
def test_the_observe_conversation_learns_what_execute_mode_did(
    servers: tuple[FakeChatServer, FakeChatServer], backend: str
) -> None:
    requests = _play(servers, backend)
    after = requests[-1]["messages"]  # the first observe call after the task was carried out
    assert after[0]["content"].startswith("You are a proactive assistant on the user's phone")
    told = after[-1]["content"]
    assert "You carried out the task the user accepted" in told
    assert "email.reply_to_email(email_id='e_ann', content='Thursday works for me!') -> ok" in told
    assert "Your report to the user: Replied to Ann: Thursday works." in told
    # and the observe conversation is the same one as before: it still holds its proposal
    assert any("Reply to Ann that Thursday works for you." in (m.get("content") or "") for m in after)


def _env() -> Environment:
    return build_environment(SCENARIO)


def test_each_actor_is_told_its_budget_and_the_life_of_a_proposal() -> None:
    budget = TurnBudget(max_turns=7, user_steps=1, observe_steps=4, execute_steps=6, proposal_ttl_turns=2)
    user = user_system_prompt(_env(), budget=budget)
    flat_user = " ".join(user.split())
    assert "the session lasts 7 turns: then it ends, whatever is unfinished" in flat_user
    assert "A proposal waits 2 turns for your answer, and shows how many it has left" in flat_user
    assert "If you cannot judge it yet" in flat_user and "reject it" in flat_user
    observe = " ".join(observe_system_prompt(_env(), budget=budget).split())
    assert "Your turn ends when you propose or wait, or after 4 actions" in observe
    assert "the session lasts 7 turns" in observe
    assert "Unanswered: the user can answer it in the 2 turns after the one you proposed in" in observe
    assert "Rejected: nothing is done" in observe
    execute = " ".join(
        execute_system_prompt(_env(), Task("Reply to Ann.", "", "proposal-1"), max_steps=6).split()
    )
    assert "at most 6 actions: if they run out before your report" in execute
    assert "do the parts that are clear, then say in your report what needs the user's decision" in execute


def test_the_loop_tells_the_actors_its_own_limits() -> None:
    seen: dict[str, str] = {}

    class Recording(LLMUser):
        def start(self, env: Environment, budget: TurnBudget = DEFAULT_BUDGET) -> None:
            super().start(env, budget)
            seen["user"] = self.conversation.messages[0].content or ""

    settings = EpisodeSettings(max_turns=4, proposal_ttl_turns=2, turn_duration=timedelta(minutes=5))
    run_episode(SCENARIO, Recording(ScriptedModel([], fallback=WAIT_USER)), SilentAssistant(), settings)
    flat = " ".join(seen["user"].split())
    assert "lasts 4 turns" in flat and "A proposal waits 2 turns" in flat


def test_long_lived_prompts_say_when_the_session_started_not_a_now_that_goes_stale() -> None:
    env = _env()
    start = env.clock.start.strftime("%A %Y-%m-%d %H:%M")
    for prompt in (user_system_prompt(env), observe_system_prompt(env)):
        assert f"started on {start}" in " ".join(prompt.split())
        assert "It is now" not in prompt
    env.advance(timedelta(hours=2))  # execute mode's prompt is written when the task starts: now is right
    execute = execute_system_prompt(env, Task("Reply to Ann.", "", "proposal-1"), max_steps=10)
    assert f"It is now {env.clock.now.strftime('%A %Y-%m-%d %H:%M')}" in execute


def test_observe_prompt_lists_what_becomes_possible_after_acceptance() -> None:
    env = build_environment(SCENARIO)
    prompt = observe_system_prompt(env)
    section = prompt.split("## Available after the user accepts (execute mode)")[1].split("##")[0]
    assert "- email__reply_to_email: " in section
    assert "- email__list_emails" not in section  # read tools are callable now, listed with the tools
    calls_now = prompt.split("## Tools you can call now")[1]
    assert "email__reply_to_email" not in calls_now


def test_each_phone_s_prompts_list_its_own_apps_tools() -> None:
    # the tool lines are worked out once per set of apps: each phone still gets its own
    for apps, present, absent in (
        (["calendar"], "calendar__add_calendar_event", "email__"),
        (["email"], "email__reply_to_email", "calendar__"),
        (["calendar", "email"], "email__reply_to_email", "contacts__"),
        (["email", "calendar"], "calendar__add_calendar_event", "contacts__"),
    ):
        env = Environment(apps)
        task = Task("Do it.", "", "proposal-1")
        for prompt in (observe_system_prompt(env), execute_system_prompt(env, task, max_steps=10)):
            assert f"- {present}" in prompt and f"- {absent}" not in prompt
        listed = execute_system_prompt(env, task, max_steps=10).split("## Tools\n")[1].split("\n#")[0]
        assert [line.split("(")[0] for line in listed.strip().splitlines()] == [
            f"- {tool.name}" for tool in env.assistant_tools("execute")
        ]


def test_nested_arguments_and_date_formats_are_spelt_out() -> None:
    env = Environment(["calendar", "contacts"])
    tools = {tool.name: tool.spec.signature for tool in env.assistant_tools("execute")}
    edit = tools["calendar__edit_calendar_event"]
    assert "updates: EventUpdate{title?: str, start_datetime?: datetime (YYYY-MM-DD HH:MM)" in edit
    assert "attendees?: list[str]}" in edit
    assert (
        "updates: ContactUpdate{first_name?: str, last_name?: str, phone?: str, email?: str"
        in tools["contacts__edit_contact"]
    )
    assert tools["calendar__get_calendar_events_from_to"].startswith(
        "get_calendar_events_from_to(start_datetime: datetime (YYYY-MM-DD HH:MM)"
    )
    # the same text reaches the model in execute mode, and in the error for wrong arguments
    prompt = execute_system_prompt(env, Task("Move it.", "", "proposal-1"), max_steps=10)
    assert "EventUpdate{title?: str" in prompt
    result = env.call("assistant", "calendar__edit_calendar_event", {"event_id": "x"}, mode="execute")
    assert result.error is not None and "EventUpdate{title?: str" in result.error


def test_tool_descriptions_are_given_once_then_listed_by_signature() -> None:
    env = _env()
    described: set[str] = set()
    first = env.user_view().render(described)
    second = env.user_view().render(described)
    assert "open_app(app_name: str): Open an app from the home screen" in first
    assert "- open_app(app_name: str)\n" in second + "\n" and "Open an app from the home screen" not in second
    assert "described earlier" in second
    assert len(second) < len(first)
    assert "Open an app from the home screen" in env.user_view().render()  # without memory: everything


def test_a_user_model_is_not_shown_the_same_descriptions_every_turn() -> None:
    user = LLMUser(ScriptedModel([], fallback=WAIT_USER))
    run_episode(SCENARIO, user, SilentAssistant(), EpisodeSettings(max_turns=3))
    observations = [m.content or "" for m in user.conversation.messages if m.role == "user"]
    assert observations[0].count("Open an app from the home screen") == 1
    assert all("Open an app from the home screen" not in text for text in observations[1:])


def test_an_expired_proposal_is_announced_to_the_user_and_the_next_one_shown_once() -> None:
    env = _env()
    env.call("assistant", "agent_ui__send_message_to_user", {"content": "Reply to Ann: yes."}, mode="observe")
    env.agent_ui.expire_pending()
    env.call("assistant", "agent_ui__send_message_to_user", {"content": "Reply to Ann: no."}, mode="observe")
    text = env.user_view().render()
    assert "withdrew its proposal: its last turn to answer ended" in text and "Reply to Ann: yes." in text
    assert text.count("Reply to Ann: no.") == 1
