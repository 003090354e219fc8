"""Whole episodes played by thinking models, through the real client (both backends) and local servers.

The user and the assistant each talk to a :class:`~pare.testing.ChatServer` that answers from a script
and, wrapped in :func:`~pare.testing.thinking`, prefixes every answer with reasoning that drafts an
``Action:`` of its own (inline as a think block, without its opening tag, or in ``reasoning_content``).
The episode must go exactly as it goes without thinking, and the trajectory must hold the reasoning.
"""

from __future__ import annotations

import asyncio
import json
import threading
from collections import deque
from collections.abc import Sequence
from typing import Any

import pytest

from pare.agents.actions import format_action
from pare.agents.llm import Conversation, LLMAssistant, LLMUser
from pare.agents.models import ChatMessage, Completion, ModelClient, ModelConfig
from pare.bench import EpisodeResult, arun_episode
from pare.testing import ChatServer, Reply, Responder, completion, thinking
from pare.testing.chat_server import THINKING
from tests.agents.models.conftest import BACKENDS
from tests.scenarios.helpers import base, parse

KEY_VARIABLE = "PARE_TEST_API_KEY"
SCENARIO = parse(base())
STYLES = ("inline", "unopened", "field")

USER_SCRIPT = [
    format_action("wait", {}, "Nothing to do yet."),
    format_action("open_app", {"app_name": "email"}, "A new email arrived; let me read it."),
    format_action("open_email", {"email_id": "e_ann"}, "Open Ann's email."),
    format_action("accept_proposal", {"reason": "Yes, exactly."}, "That is what I want."),
    format_action("wait", {}, "Done."),
]
ASSISTANT_SCRIPT = [
    format_action("system__wait", {}, "Nothing yet."),
    format_action("system__wait", {}, "Still nothing."),
    format_action("email__get_email_by_id", {"email_id": "e_ann"}, "Read Ann's email before proposing."),
    format_action(
        "agent_ui__send_message_to_user", {"content": "Reply to Ann that Thursday works for you."}, "Propose."
    ),
    format_action("email__reply_to_email", {"email_id": "e_ann", "content": "Thursday works for me!"}, "Go."),
    format_action("agent_ui__send_message_to_user", {"content": "Replied to Ann: Thursday works."}, "Tell."),
    format_action("system__wait", {}, "Done."),
]


@pytest.fixture(autouse=True)
def api_key(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv(KEY_VARIABLE, "sk-test-not-a-real-key")


def scripted(answers: list[str]) -> Responder:
    """Answers with ``answers`` in order, whatever was asked."""
    queue = deque(answers)
    lock = threading.Lock()

    def respond(body: dict[str, Any]) -> Reply:
        with lock:
            return completion(queue.popleft(), 500, 40)

    return respond


def play(backend: str, style: str | None) -> tuple[EpisodeResult, list[dict[str, Any]]]:
    """The scripted episode; returns it and every request the two servers received."""
    user_responder, assistant_responder = scripted(USER_SCRIPT), scripted(ASSISTANT_SCRIPT)
    if style is not None:
        user_responder = thinking(user_responder, style=style)  # type: ignore[arg-type]
        assistant_responder = thinking(assistant_responder, style=style)  # type: ignore[arg-type]
    with ChatServer(user_responder) as user_server, ChatServer(assistant_responder) as assistant_server:

        def client(server: ChatServer, role: str) -> ModelClient:
            config = ModelConfig(
                model="openai/pare-test-model" if backend == "litellm" else "pare-test-model",
                backend=backend,  # type: ignore[arg-type]
                api_base=server.base_url,
                api_key_env=KEY_VARIABLE,
                max_retries=0,
                prices={"input": 1.0, "output": 2.0},  # type: ignore[arg-type]
            )
            return ModelClient(config, role=role)

        user_model, assistant_model = client(user_server, "user"), client(assistant_server, "observe")

        async def episode() -> EpisodeResult:
            async with user_model, assistant_model:
                return await arun_episode(SCENARIO, LLMUser(user_model), LLMAssistant(assistant_model))

        result = asyncio.run(episode())
        return result, user_server.requests + assistant_server.requests


def model_steps(result: EpisodeResult) -> list[dict[str, Any]]:
    steps: list[dict[str, Any]] = result.to_dict()["steps"]
    return [step for step in steps if step["action"]["usage"] is not None]


@pytest.mark.parametrize("backend", BACKENDS)
@pytest.mark.parametrize("style", STYLES)
def test_a_thinking_model_plays_the_episode_as_without_thinking(backend: str, style: str) -> None:
    plain, _ = play(backend, None)
    result, requests = play(backend, style)

    assert plain.success and result.success, result.outcome.failures()
    assert [(s.turn, s.actor, s.mode, s.action.tool, s.action.args) for s in result.steps] == [
        (s.turn, s.actor, s.mode, s.action.tool, s.action.args) for s in plain.steps
    ]
    steps = model_steps(result)
    assert len(steps) == len(USER_SCRIPT) + len(ASSISTANT_SCRIPT)
    for step, plain_step in zip(steps, model_steps(plain), strict=True):
        action = step["action"]
        assert action["usage"]["format_errors"] == [] and action["usage"]["calls"] == 1
        assert action["reasoning"] == THINKING  # kept in the trajectory...
        assert action["raw"] == plain_step["action"]["raw"]  # ...apart from the answer
        assert plain_step["action"]["reasoning"] is None
        # the reasoning's tokens count as completion tokens
        assert action["usage"]["completion_tokens"] > plain_step["action"]["usage"]["completion_tokens"]

    # the reasoning never went back to a model
    sent = [m for request in requests for m in request["messages"] if m["role"] == "assistant"]
    assert sent
    for message in sent:
        assert set(message) <= {"role", "content", "tool_calls"}
        assert "think>" not in message["content"] and "draft_from_thinking" not in message["content"]
    assert json.dumps(result.to_dict()).count("draft_from_thinking") == len(steps)  # once per reasoning


class Scripted:
    """A chat model that answers from a list of completions and keeps the conversations it was sent."""

    def __init__(self, *answers: Completion) -> None:
        self.answers = deque(answers)
        self.sent: list[list[ChatMessage]] = []

    async def complete(
        self, messages: Sequence[ChatMessage], tools: Sequence[dict[str, Any]] | None = None
    ) -> Completion:
        self.sent.append(list(messages))
        return self.answers.popleft()


def answer(text: str, reasoning: str | None = None) -> Completion:
    return Completion(text=text, reasoning=reasoning, cost_usd=None, latency_s=0.0, model="m")


@pytest.mark.parametrize(
    ("first", "recorded"),
    [
        (answer("", reasoning=THINKING), THINKING),
        (answer(f"<think>{THINKING}</think>"), THINKING),
        (answer(f"{THINKING}</think>\n"), THINKING),
    ],
    ids=["field", "inline", "unopened"],
)
def test_an_answer_that_is_only_thinking_gets_a_format_error_for_the_model(
    first: Completion, recorded: str
) -> None:
    model = Scripted(first, answer(ASSISTANT_SCRIPT[0]))
    conversation = Conversation(model)
    conversation.reset("You are the assistant.")
    conversation.tell("Nothing new.")
    action = asyncio.run(conversation.decide())

    assert action.tool == "system__wait" and action.error is None
    assert action.usage is not None and action.usage.calls == 2
    (error,) = action.usage.format_errors
    assert "only your reasoning" in error and "no Action: section" in error
    retry = model.sent[1]
    assert [m.role for m in retry[-2:]] == ["assistant", "user"]
    assert retry[-2].content == ""  # the answer, without its reasoning
    assert retry[-1].content == f"Error: {error}"
    assert action.reasoning is None  # the reasoning of the answer that made the action (it had none)


def test_a_step_whose_answers_stay_only_thinking_fails_with_the_reasoning_recorded() -> None:
    model = Scripted(*[answer(f"<think>{THINKING}</think>")] * 3)
    conversation = Conversation(model, max_format_retries=2)
    conversation.reset("You are the assistant.")
    conversation.tell("Nothing new.")
    action = asyncio.run(conversation.decide())
    assert action.error is not None and "only your reasoning" in action.error
    assert action.raw == "" and action.reasoning == THINKING
