"""Model-backed actors driven by scripted models: mode transitions, format retries, failed steps."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import pytest

from pare.agents.actions import format_action
from pare.agents.judge import ModelJudge
from pare.agents.llm import LLMAssistant, LLMUser
from pare.agents.models import ChatMessage, Completion, ToolCall
from pare.agents.scripted import ScriptedModel, ScriptExhausted
from pare.bench import EpisodeSettings, run_episode
from pare.scenarios import OracleAssistant, OracleUser
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
    assert first.action.usage is not None and len(first.action.usage.format_errors) == 3
    assert not [entry for entry in result.env.log.entries if entry.actor == "user" and entry.turn == 1]


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


class NativeModel:
    """Answers with native tool calls, recording the conversations it gets."""

    def __init__(self, calls: list[tuple[str, str]]) -> None:
        self.calls = calls
        self.requests: list[list[Any]] = []
        self.tools: list[Any] = []

    async def complete(
        self, messages: Sequence[ChatMessage], tools: Sequence[dict[str, Any]] | None = None
    ) -> Completion:
        self.requests.append(list(messages))
        self.tools.append(tools)
        name, arguments = self.calls.pop(0) if self.calls else ("wait", "{}")
        call = ToolCall(id=f"call-{len(self.requests)}", name=name, arguments=arguments)
        return Completion(text="", tool_calls=(call,), cost_usd=0.0, latency_s=0.0, model="native")


def test_native_tool_calling_sends_schemas_and_answers_calls_with_tool_messages() -> None:
    model = NativeModel([("wait", "{}"), ("open_app", '{"app_name": "email"}'), ("open_app", "[1]")])
    user = LLMUser(model, native_tools=True)
    run_episode(
        SCENARIO, user, LLMAssistant(ScriptedModel([], fallback=WAIT_ASSISTANT)), EpisodeSettings(max_turns=3)
    )
    assert model.tools[0] is not None and any(t["function"]["name"] == "open_app" for t in model.tools[0])
    assert "Action:" not in (model.requests[0][0].content or "")  # no text format in the native prompt
    second = model.requests[1]
    assert second[-2].role == "assistant" and second[-2].tool_calls is not None
    assert second[-1].role == "tool" and second[-1].tool_call_id == "call-1"
    third = model.requests[3]  # the bad arguments were sent back as an error
    assert third[-1].content is not None and "must be a JSON object" in third[-1].content


def test_a_native_assistant_is_sent_the_schemas_of_its_mode_and_a_text_one_none() -> None:
    observe = NativeModel([("system__wait", "{}")])
    run_episode(
        SCENARIO,
        LLMUser(ScriptedModel([], fallback=WAIT_USER)),
        LLMAssistant(observe, native_tools=True),
        EpisodeSettings(max_turns=1),
    )
    names = {schema["function"]["name"] for schema in observe.tools[0]}
    assert {"email__list_emails", "system__wait", "agent_ui__send_message_to_user"} <= names
    assert "email__reply_to_email" not in names  # a write tool: execute mode only

    class TextModel(NativeModel):
        async def complete(
            self, messages: Sequence[ChatMessage], tools: Sequence[dict[str, Any]] | None = None
        ) -> Completion:
            self.tools.append(tools)
            return Completion(text=WAIT_ASSISTANT, cost_usd=0.0, latency_s=0.0, model="text")

    text = TextModel([])
    run_episode(
        SCENARIO,
        LLMUser(ScriptedModel([], fallback=WAIT_USER)),
        LLMAssistant(text),
        EpisodeSettings(max_turns=1),
    )
    assert text.tools == [None]  # the text format lists the tools in the prompt instead


def test_a_model_judge_decides_judge_checks_and_only_a_clear_yes_passes() -> None:
    data = base()
    data["goals"][0]["checks"] = [
        {
            "judge": {
                "criterion": "accepts Thursday politely",
                "action": {"tool": "email__reply_to_email"},
                "fallback": {"contains": "thursday"},
            }
        }
    ]
    scenario = parse(data)
    for answer, passed in (("YES", True), ("Yes, it does.", True), ("NO", False), ("Probably", False)):
        model = ScriptedModel([answer])
        judge = ModelJudge(model)
        result = run_episode(scenario, OracleUser(scenario), OracleAssistant(scenario), judge=judge)
        assert result.success is passed, answer
        assert "Thursday works!" in (model.requests[0][1].content or "")
        (judged,) = result.outcome.goals[0].checks[0].judged
        assert (judged.verdict.passed, judged.verdict.answer) == (passed, answer)
