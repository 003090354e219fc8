"""A thinking model's reasoning, as servers return it, reaches the completion apart from its answer, and
survives the record/replay cache."""

from __future__ import annotations

import asyncio
import json
import sqlite3
from pathlib import Path
from typing import Any

import pytest

from pare.agents.models import ChatMessage, Completion, ModelCallCache, ModelClient, ModelConfig
from pare.testing import ChatServer, Reply, completion

from .conftest import BACKENDS, KEY_VARIABLE

HELLO = [ChatMessage.system("You are terse."), ChatMessage.user("Say hello.")]
ANSWER = "Thought: greet.\n\nAction:\n{}"
THOUGHT = 'Should I say hi? Action: {"action": "x"} would be wrong here.'


def config(server: ChatServer, backend: str) -> ModelConfig:
    return ModelConfig(
        model="openai/pare-test-model" if backend == "litellm" else "pare-test-model",
        backend=backend,  # type: ignore[arg-type]
        api_base=server.base_url,
        api_key_env=KEY_VARIABLE,
        max_retries=0,
    )


def ask(server: ChatServer, backend: str, cache: ModelCallCache | None = None) -> Completion:
    async def call() -> Completion:
        async with ModelClient(config(server, backend), role="user", cache=cache) as client:
            return await client.complete(HELLO)

    return asyncio.run(call())


def with_field(name: str, value: str, text: str = ANSWER) -> Reply:
    reply = completion(text)
    body: dict[str, Any] = json.loads(json.dumps(reply.body))
    body["choices"][0]["message"][name] = value
    return Reply(200, body)


@pytest.mark.parametrize("backend", BACKENDS)
@pytest.mark.parametrize(
    ("reply", "reasoning"),
    [
        (completion(ANSWER, reasoning=THOUGHT), THOUGHT),
        (with_field("reasoning", THOUGHT), THOUGHT),
        (completion(f"<think>\n{THOUGHT}\n</think>\n\n{ANSWER}"), THOUGHT),
        (completion(f"{THOUGHT}\n</think>\n\n{ANSWER}"), THOUGHT),  # <think> was in the prompt
        (completion(f"<think>inline</think>{ANSWER}", reasoning=THOUGHT), f"{THOUGHT}\n\ninline"),
        (completion(f"<think></think>\n\n{ANSWER}"), None),  # thinking switched off
        (completion(ANSWER), None),
    ],
    ids=["reasoning_content", "reasoning", "inline", "unopened", "field-and-inline", "empty-block", "none"],
)
def test_reasoning_is_taken_apart_from_the_answer(backend: str, reply: Reply, reasoning: str | None) -> None:
    with ChatServer(lambda body: reply) as server:
        answer = ask(server, backend)
    assert answer.text == ANSWER
    assert answer.reasoning == reasoning
    assert answer.message().content == ANSWER  # what goes back into the conversation


def test_the_cache_keeps_the_reasoning(tmp_path: Path) -> None:
    path = tmp_path / "calls.sqlite"
    with ChatServer(lambda body: completion(f"<think>{THOUGHT}</think>{ANSWER}")) as server:
        live = ask(server, "openai", ModelCallCache(path, "read_write"))
        replayed = ask(server, "openai", ModelCallCache(path, "replay"))
        assert server.request_count == 1
    assert live.reasoning == THOUGHT and live.text == ANSWER
    assert replayed.from_cache and (replayed.reasoning, replayed.text) == (THOUGHT, ANSWER)
    with sqlite3.connect(path) as connection:
        (stored,) = connection.execute("SELECT completion FROM completions").fetchone()
    assert json.loads(stored)["reasoning"] == THOUGHT


def test_entries_recorded_without_a_reasoning_field_still_replay(tmp_path: Path) -> None:
    path = tmp_path / "calls.sqlite"
    with ChatServer(lambda body: completion(ANSWER)) as server:
        ask(server, "openai", ModelCallCache(path, "read_write"))
        with sqlite3.connect(path) as connection:  # as an older PARE wrote it
            (stored,) = connection.execute("SELECT completion FROM completions").fetchone()
            older = {key: value for key, value in json.loads(stored).items() if key != "reasoning"}
            connection.execute("UPDATE completions SET completion = ?", (json.dumps(older),))
        replayed = ask(server, "openai", ModelCallCache(path, "replay"))
    assert replayed.from_cache and replayed.text == ANSWER and replayed.reasoning is None
