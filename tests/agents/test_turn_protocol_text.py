"""What the turn protocol tells the models, through the real turn loop: the turn counter in every
observation, why the clock jumped, how long a proposal can still be answered, execute mode's action count,
what execute mode did in the order it happened, and a closing observation that ends each conversation.
"""

from __future__ import annotations

import json
import re
from typing import Any

import pytest

from pare.agents.actions import format_action
from pare.agents.llm import LLMAssistant, LLMUser
from pare.agents.prompts import example_for, observe_system_prompt, user_system_prompt
from pare.agents.scripted import ScriptedModel
from pare.bench import EpisodeSettings, run_episode
from pare.bench.episode import EpisodeResult, duration_words
from pare.bench.runconfig import ProtocolSettings
from pare.env import Environment
from pare.sim.budget import DEFAULT_BUDGET
from tests.agents.test_scripted_actors import WAIT_ASSISTANT, WAIT_USER
from tests.scenarios.helpers import base, parse

SCENARIO = parse(base())  # Ann's email arrives 5 minutes in; the goal is a reply that says Thursday


def _say(tool: str, args: dict[str, Any] | None = None) -> str:
    return format_action(tool, args or {}, "Next step.")


USER = [
    _say("wait"),  # turn 1: both wait, so the clock jumps to Ann's email
    _say("open_app", {"app_name": "email"}),  # turn 2
    _say("open_email", {"email_id": "e_ann"}),  # turn 3: the proposal waits
    _say("accept_proposal"),  # turn 4: the task is carried out
    _say("go_back"),  # turn 5
]
ASSISTANT = [
    WAIT_ASSISTANT,  # turn 1
    _say("email__get_email_by_id", {"email_id": "e_ann"}),  # turn 2
    _say("agent_ui__send_message_to_user", {"content": "Reply to Ann that Thursday works for you."}),
    _say("email__get_email_by_id", {"email_id": "e_ann"}),  # turn 4, execute mode
    _say("email__reply_to_email", {"email_id": "e_ann", "content": "Thursday works for me!"}),
    _say("agent_ui__send_message_to_user", {"content": "Replied to Ann: Thursday works."}),
]


def _play(
    max_turns: int, user_script: list[str] = USER, assistant_script: list[str] = ASSISTANT, ttl: int = 3
) -> tuple[LLMUser, LLMAssistant, EpisodeResult]:
    user = LLMUser(ScriptedModel(list(user_script), fallback=WAIT_USER))
    assistant = LLMAssistant(ScriptedModel(list(assistant_script), fallback=WAIT_ASSISTANT))
    result = run_episode(
        SCENARIO, user, assistant, EpisodeSettings(max_turns=max_turns, proposal_ttl_turns=ttl)
    )
    return user, assistant, result


def _told(messages: list[Any]) -> list[str]:
    return [m.content or "" for m in messages if m.role != "assistant"][1:]  # past the system prompt


def test_every_observation_states_the_turn_and_execute_mode_counts_its_actions() -> None:
    user, assistant, result = _play(max_turns=6)
    assert result.success, result.outcome.failures()
    told_user = _told(user.conversation.messages)
    assert [re.search(r"Turn (\d) of 6\. Current time", text) is not None for text in told_user[:-1]] == [
        True
    ] * (len(told_user) - 1)
    observed = _told(assistant.observer.messages)
    assert observed[0].startswith("Turn 1 of 6. Current time:")
    # a later action of the same turn says where it stands in the turn
    assert observed[2].endswith("Turn 2 of 6; action 2 of 5 this turn.")
    executed = _told(assistant.executor.messages)
    assert executed[0].endswith("Action 1 of 10.")
    assert executed[1].endswith("Action 2 of 10.") and executed[2].endswith("Action 3 of 10.")


def test_a_clock_jump_is_told_with_its_size_and_reason_once_per_actor() -> None:
    user, assistant, _ = _play(max_turns=6)
    jumped = "the clock jumped 5 minutes: nothing was happening until the next event"
    told_user = _told(user.conversation.messages)
    assert jumped in told_user[1] and "Turn 2 of 6" in told_user[1]
    assert all(jumped not in text for text in told_user[2:])  # turns of one minute say nothing
    observed = _told(assistant.observer.messages)
    assert jumped in observed[1]
    assert sum(jumped in text for text in observed) == 1


def test_duration_words() -> None:
    from datetime import timedelta

    assert duration_words(timedelta(minutes=14)) == "14 minutes"
    assert duration_words(timedelta(hours=1, minutes=1)) == "1 hour 1 minute"
    assert duration_words(timedelta(days=2, hours=3)) == "2 days 3 hours"
    assert duration_words(timedelta(seconds=30)) == "less than a minute"


def test_the_pending_proposal_shows_the_turns_left_and_is_withdrawn_after_the_last() -> None:
    never_answers = [_say("wait"), _say("open_app", {"app_name": "email"}), *[_say("wait")] * 5]
    user, _, result = _play(max_turns=7, user_script=never_answers, assistant_script=ASSISTANT[:3])
    told_user = _told(user.conversation.messages)
    assert "It can be answered this turn and 2 more; then, unanswered, it is withdrawn." in told_user[2]
    assert "It can be answered this turn and 1 more" in told_user[3]
    last_chance = told_user[4]
    last_turn = "This is the last turn to answer it: unanswered, it is withdrawn at the end of this turn."
    assert last_turn in last_chance
    assert "accept_proposal" in last_chance  # it can still be accepted then
    after = told_user[5]  # nothing else to come: the episode ends, and the closing observation says so
    assert "withdrew its proposal" in after and "accept_proposal" not in after
    assert "The assistant proposes" not in after and "The session is over after turn 5 of 7" in after
    assert result.expired_at == {"proposal-1": 5}
    views = [step.view for step in result.steps if step.view is not None]
    assert [view.get("proposal_turns_left") for view in views] == [None, None, 3, 2, 1]


def test_a_proposal_waits_four_turns_by_default_and_the_prompts_say_so() -> None:
    # checking one thing in another app takes three actions (home, open the app, open the item): four
    # turns leave room for the answer after it
    assert EpisodeSettings().proposal_ttl_turns == 4 == EpisodeSettings().budget().proposal_ttl_turns
    assert ProtocolSettings().proposal_ttl_turns == 4 == DEFAULT_BUDGET.proposal_ttl_turns
    env = Environment(["email"])
    assert "A proposal waits 4 turns for your answer" in " ".join(user_system_prompt(env).split())
    assert "answer it in the 4 turns after the one you proposed in" in " ".join(
        observe_system_prompt(env).split()
    )


def test_execution_is_told_after_the_acceptance_with_every_call_in_order() -> None:
    _, assistant, _ = _play(max_turns=6)
    told = next(text for text in _told(assistant.observer.messages) if "You carried out" in text)
    order = [
        "User actions:",
        "email.open_email(email_id='e_ann') -> ok",
        "agent_ui.accept_proposal() -> ok",
        "You carried out the task the user accepted (execute mode), in this order:",
        "- read: email.get_email_by_id(email_id='e_ann') -> ok",
        "- change: email.reply_to_email(email_id='e_ann', content='Thursday works for me!') -> ok",
        "Your report to the user: Replied to Ann: Thursday works.",
        "User actions since:",
        "system.go_back() -> ok",
    ]
    positions = [told.index(line) for line in order]
    assert positions == sorted(positions), told
    assert "read call" not in told


def test_each_conversation_ends_with_a_closing_observation_without_a_call() -> None:
    # the user accepts in the last turn: the task's result reaches both only in the closing observation
    user, assistant, result = _play(max_turns=4)
    user_model = user.conversation.model
    assert isinstance(user_model, ScriptedModel)
    calls = len(user_model.requests)
    closing_user = user.conversation.messages[-1].content or ""
    assert user.conversation.messages[-1].role == "user"
    assert closing_user.startswith("Observation: ")  # the last action's result
    assert "Message from your assistant" in closing_user and "Replied to Ann: Thursday works." in closing_user
    assert closing_user.endswith(
        "The session is over after turn 4 of 4: that was its last turn. "
        "Nothing more will happen and no answer is expected."
    )
    closing_assistant = assistant.observer.messages[-1].content or ""
    assert "You carried out the task the user accepted" in closing_assistant
    assert "The session is over after turn 4 of 4" in closing_assistant
    assert len(user_model.requests) == calls == 4  # one call a turn, none for the closing
    assert result.closing == {"user": closing_user, "assistant": closing_assistant}
    assert json.loads(json.dumps(result.to_dict()))["closing"]["user"] == closing_user


def test_an_idle_end_is_named_as_such() -> None:
    user, _, result = _play(max_turns=8)
    assert result.ended == "idle"
    assert (user.conversation.messages[-1].content or "").endswith(
        f"after turn {result.turns} of 8: nothing more was going to happen. "
        "Nothing more will happen and no answer is expected."
    )


PHONES = (["calendar", "email"], ["email"], ["messaging", "contacts"], ["shopping"], ["apartment"], ["cab"])


@pytest.mark.parametrize("apps", PHONES)
def test_the_example_answers_call_the_phone_s_own_tools_in_their_formats(apps: list[str]) -> None:
    env = Environment(apps)
    for role, actor, mode in (("observe", "assistant", "observe"), ("execute", "assistant", "execute")):
        example = example_for(env, role)  # type: ignore[arg-type]
        action = json.loads(example.split("Action:\n")[1].removesuffix("<end_action>"))
        result = env.call(actor, action["action"], action["action_input"], mode=mode)  # type: ignore[arg-type]
        assert result.ok, (apps, role, result.error)
    user = json.loads(example_for(env, "user").split("Action:\n")[1].removesuffix("<end_action>"))
    assert user["action_input"]["app_name"] in apps
    assert env.call("user", user["action"], user["action_input"]).ok
    assert ":00:00" not in observe_system_prompt(env)  # the tools take YYYY-MM-DD HH:MM


def test_prompts_say_each_thing_about_notifications_once_and_which_arrive_whole() -> None:
    env = Environment(["email"])
    observe = " ".join(observe_system_prompt(env).split())
    assert observe.count("in full") == 1
    user = " ".join(user_system_prompt(env).split())
    assert "the first 12 words" in user
    assert "Your assistant's messages to you (its reports" in user and "always shown in full" in user
    # and so they are: a long report reaches a user at the preview level whole
    report = " ".join(["word"] * 40) + " end."
    env.call("assistant", "agent_ui__send_message_to_user", {"content": "Do it."}, mode="observe")
    env.call("user", "accept_proposal", {})
    env.call("assistant", "agent_ui__send_message_to_user", {"content": report}, mode="execute")
    assert any(report in n for n in env.user_view().notifications)
