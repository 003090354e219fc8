"""Model-backed actors driven by scripted models: mode transitions, format retries, failed steps."""

from __future__ import annotations

import pytest

from pare.agents.actions import format_action
from pare.agents.llm import LLMAssistant, LLMUser
from pare.agents.scripted import ScriptedModel, ScriptExhausted
from pare.bench import EpisodeSettings, run_episode
from tests.scenarios.helpers import base, parse

SCENARIO = parse(base())
WAIT_USER = format_action("wait", {}, "Nothing to do.")
WAIT_ASSISTANT = format_action("system__wait", {}, "Nothing to do.")


def test_malformed_answers_are_retried_then_the_step_fails_without_touching_the_phone() -> None:
    user = LLMUser(ScriptedModel(["no idea", "still no idea", "{not json"], fallback=WAIT_USER))
    assistant = LLMAssistant(ScriptedModel([], fallback=WAIT_ASSISTANT))
    result = run_episode(SCENARIO, user, assistant, EpisodeSettings(max_turns=2))
    first = result.steps[0]
    assert first.actor == "user" and not first.ok and first.log_index is None
    assert first.action.error is not None and "No valid action after 3 answers" in first.action.error
    assert first.action.usage is not None and len(first.action.usage["format_errors"]) == 3
    assert all(entry.actor != "user" for entry in result.env.log.entries[:1])


def test_scripted_models_play_a_whole_episode() -> None:
    user = LLMUser(
        ScriptedModel(
            [
                WAIT_USER,
                format_action("open_app", {"app_name": "email"}),
                format_action("open_email", {"email_id": "e_ann"}),
                format_action("accept_proposal", {"reason": "yes"}),
            ],
            fallback=WAIT_USER,
        )
    )
    observe = ScriptedModel(
        [
            WAIT_ASSISTANT,
            WAIT_ASSISTANT,
            format_action("agent_ui__send_message_to_user", {"content": "Reply to Ann that Thursday works."}),
        ],
        fallback=WAIT_ASSISTANT,
    )
    execute = ScriptedModel(
        [
            format_action("email__reply_to_email", {"email_id": "e_ann", "content": "Thursday works!"}),
            format_action("agent_ui__send_message_to_user", {"content": "Done."}),
        ]
    )
    result = run_episode(SCENARIO, user, LLMAssistant(observe, execute))
    assert result.success
    assert len(execute.requests) == 2 and execute.requests[0][0].role == "system"
    assert "Reply to Ann that Thursday works." in (execute.requests[0][0].content or "")
    # the observe conversation carried on across turns; its proposal's result came back next turn
    assert any("proposal-1" in (m.content or "") for m in observe.requests[-1])


def test_an_exhausted_script_is_a_clear_error() -> None:
    with pytest.raises(ScriptExhausted, match="no answer left"):
        run_episode(SCENARIO, LLMUser(ScriptedModel([])), LLMAssistant(ScriptedModel([])))
