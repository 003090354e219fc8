"""Whatever a model or its provider returns ends as the model's outcome or a provider fault, never as a
crashed run or a file that is not valid JSON.

Every test goes through the real client path: ``pare run`` or :class:`~pare.agents.models.ModelClient`
against a :class:`~pare.testing.ChatServer` on 127.0.0.1 whose answers are rewritten to be hostile.
"""

from __future__ import annotations

import json
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import pytest

from pare.agents.actions import format_action
from pare.agents.models import ModelClient, ModelConfig
from pare.agents.models.types import ChatMessage
from pare.cli import main
from pare.errors import ProviderUnavailable
from pare.results.run_folder import EPISODES
from pare.testing import ChatServer, Reply, completion, conversation_role, proactive_play
from tests.hardening.conftest import KEY_VARIABLE, strict_json

Rewrite = Callable[[dict[str, Any], Reply], Reply]


def _answer_text(reply: Reply) -> str:
    return str(reply.body["choices"][0]["message"]["content"])


def _with_text(reply: Reply, text: str) -> Reply:
    body = json.loads(json.dumps(reply.body))
    body["choices"][0]["message"]["content"] = text
    return Reply(reply.status, body, reply.headers)


def _hostile(rewrite: Rewrite) -> Callable[[dict[str, Any]], Reply]:
    play = proactive_play()

    def respond(request: dict[str, Any]) -> Reply:
        return rewrite(request, play(request))

    return respond


@pytest.fixture
def server() -> Iterator[ChatServer]:
    with ChatServer(proactive_play()) as chat:
        yield chat


def run_command(output: Path, scenario: Path, server: ChatServer, *extra: str) -> list[str]:
    argv = ["run", "--output", str(output), "--no-progress", "--runs", "1", "--scenario-path", str(scenario)]
    argv += ["--user-model", "u", "--user-endpoint", server.base_url]
    argv += ["--assistant-model", "a", "--assistant-endpoint", server.base_url]
    for role in ("user", "assistant"):
        argv += ["--set", f"models.{role}.api_key_env={KEY_VARIABLE}"]
        argv += ["--set", f"models.{role}.retry_initial_s=0.001", "--set", f"models.{role}.retry_max_s=0.01"]
        argv += ["--set", f"models.{role}.max_retries=1"]
    return [*argv, "--set", "episode_retries=0", *extra]


def only_record(output: Path) -> dict[str, Any]:
    lines = (output / EPISODES).read_text(encoding="utf-8").splitlines()
    assert len(lines) == 1
    record: dict[str, Any] = strict_json(lines[0])
    return record


def trajectory_text(output: Path, record: dict[str, Any]) -> str:
    return (output / record["trajectory"]).read_bytes().decode("utf-8")  # valid UTF-8 or this raises


# -- lone surrogates -------------------------------------------------------------------------------------
def _surrogate_in_proposal(request: dict[str, Any], reply: Reply) -> Reply:
    if conversation_role(request["messages"]) == "observe" and "Shall I" in _answer_text(reply):
        return _with_text(reply, _answer_text(reply).replace("Shall I", "Shall \ud800 I"))
    return reply


def _escaped_surrogate_in_arguments(request: dict[str, Any], reply: Reply) -> Reply:
    if conversation_role(request["messages"]) == "observe" and "Shall I" in _answer_text(reply):
        # The JSON escape is plain ASCII in the answer; decoding the action makes it a lone surrogate.
        return _with_text(reply, _answer_text(reply).replace("Shall I", "Shall \\ud800 I"))
    return reply


@pytest.mark.parametrize(
    "rewrite", [_surrogate_in_proposal, _escaped_surrogate_in_arguments], ids=["in_text", "escaped_in_args"]
)
def test_a_lone_surrogate_is_the_models_text_and_every_file_stays_valid(
    tmp_path: Path, example_scenario: Path, server: ChatServer, rewrite: Rewrite
) -> None:
    server.responder = _hostile(rewrite)
    output = tmp_path / "run"
    assert main(run_command(output, example_scenario, server)) == 0
    record = only_record(output)
    assert record["status"] == "complete", record["failure"]
    assert "Shall \ufffd I go ahead?" in record["proposals"][0]["content"]
    trajectory = strict_json(trajectory_text(output, record))
    assert "\ufffd" in json.dumps(trajectory, ensure_ascii=False)

    # The answer is in the cache: a replay of the same episode gives the same file, byte for byte.
    first = trajectory_text(output, record)
    (output / EPISODES).unlink()
    assert main(run_command(output, example_scenario, server, "--cache", "replay")) == 0
    assert trajectory_text(output, only_record(output)) == first


# -- NaN and Infinity in native tool calls ------------------------------------------------------------------
def _nan_tool_call(request: dict[str, Any], reply: Reply) -> Reply:
    if conversation_role(request["messages"]) != "observe" or "tools" not in request:
        return reply
    body = json.loads(json.dumps(reply.body))
    body["choices"][0]["message"] = {
        "role": "assistant",
        "content": None,
        "tool_calls": [
            {
                "id": "call_1",
                "type": "function",
                "function": {"name": "system__wait", "arguments": '{"minutes": NaN, "x": Infinity}'},
            }
        ],
    }
    return Reply(200, body)


def test_nan_in_native_tool_arguments_is_a_format_error_not_a_broken_file(
    tmp_path: Path, example_scenario: Path, server: ChatServer
) -> None:
    server.responder = _hostile(_nan_tool_call)
    output = tmp_path / "run"
    native = ["--set", "models.assistant.native_tools=true"]
    assert main(run_command(output, example_scenario, server, *native)) == 0
    record = only_record(output)
    assert record["status"] == "complete", record["failure"]
    text = trajectory_text(output, record)
    strict_json(text)
    assert "NaN, which is not a JSON number" in text


# -- provider faults behind a 200 ---------------------------------------------------------------------------
GOOD = completion(format_action("system__wait", {}, "ok"))
BROKEN_200 = {
    "truncated": Reply(200, raw=b'{"id": "x", "object": "chat.completion", "choices": [{"index": 0, "mess'),
    "empty": Reply(200, raw=b""),
    "not_utf8": Reply(200, raw=json.dumps(GOOD.body).replace("ok", "caf\u00e9").encode("latin-1")),
    "negative_usage": Reply(200, {**GOOD.body, "usage": {"prompt_tokens": -5, "completion_tokens": 3}}),
    "fractional_usage": Reply(200, {**GOOD.body, "usage": {"prompt_tokens": 1.5, "completion_tokens": 3}}),
    "no_choices": Reply(200, {**GOOD.body, "choices": []}),
}


def _client(server: ChatServer, retries: int) -> ModelClient:
    config = ModelConfig(
        model="m",
        api_base=server.base_url,
        api_key_env=KEY_VARIABLE,
        max_retries=retries,
        retry_initial_s=0.001,
        retry_max_s=0.01,
    )
    return ModelClient(config, role="observe")


@pytest.mark.parametrize("fault", sorted(BROKEN_200))
def test_a_broken_200_is_retried_then_a_provider_fault(server: ChatServer, fault: str) -> None:
    answers = iter([BROKEN_200[fault], GOOD])
    server.responder = lambda _request: next(answers)
    answer = _client(server, retries=2).complete_sync([ChatMessage.user("hi")])
    assert answer.text == _answer_text(GOOD)
    assert server.request_count == 2  # retried once, then the good answer

    server.reset()
    server.responder = lambda _request: BROKEN_200[fault]
    with pytest.raises(ProviderUnavailable, match="infrastructure failure"):
        _client(server, retries=1).complete_sync([ChatMessage.user("hi")])
    assert server.request_count == 2


def test_a_provider_that_keeps_answering_garbage_is_missing_coverage(
    tmp_path: Path, example_scenario: Path, server: ChatServer
) -> None:
    server.responder = lambda _request: BROKEN_200["truncated"]
    output = tmp_path / "run"
    assert main(run_command(output, example_scenario, server)) == 1  # 1: some episodes missing coverage
    record = only_record(output)
    assert record["status"] == "failed"
    assert record["failure"]["kind"] == "provider_unavailable"
