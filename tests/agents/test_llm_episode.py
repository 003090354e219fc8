"""Full episodes with model-backed actors, through the real client (both backends) and a local server.

The user and the assistant each talk to their own OpenAI-compatible server on 127.0.0.1 that answers from
a script in the paper's text format, so the whole path runs: prompts, the client, parsing, the turn loop,
the environment and the checks.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import pytest

from pare.agents.actions import format_action
from pare.agents.llm import LLMAssistant, LLMUser
from pare.agents.models import ModelCallCache, ModelClient, ModelConfig, UsageLedger
from pare.bench import EpisodeResult, run_episode
from tests.agents.models.conftest import BACKENDS
from tests.agents.models.fake_server import FakeChatServer, answer
from tests.scenarios.helpers import base, parse

KEY_VARIABLE = "PARE_TEST_API_KEY"
SCENARIO = parse(base())


@pytest.fixture(autouse=True)
def api_key(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv(KEY_VARIABLE, "sk-test-not-a-real-key")


def _config(server: FakeChatServer, backend: str) -> ModelConfig:
    return ModelConfig(
        model="openai/pare-test-model" if backend == "litellm" else "pare-test-model",
        backend=backend,  # type: ignore[arg-type]
        api_base=server.base_url,
        api_key_env=KEY_VARIABLE,
        max_retries=1,
        retry_initial_s=0.001,
        retry_max_s=0.01,
        prices={"input": 1.0, "output": 2.0},  # type: ignore[arg-type]
    )


def _say(tool: str, args: dict[str, Any] | None = None, thought: str = "Next step.") -> Any:
    return answer(format_action(tool, args or {}, thought), prompt_tokens=500, completion_tokens=40)


USER_ACCEPTS = [
    _say("wait", thought="Nothing to do yet."),
    _say("open_app", {"app_name": "email"}, "A new email arrived; let me read it."),
    _say("open_email", {"email_id": "e_ann"}),
    _say("accept_proposal", {"reason": "Yes, exactly."}),
    _say("wait"),
]
ASSISTANT_SCRIPT = [
    answer("I think I should wait."),  # malformed: no Action, fed back with a hint
    _say("system__wait"),
    _say("system__wait"),
    _say("email__get_email_by_id", {"email_id": "e_ann"}, "Read Ann's email before proposing."),
    _say("agent_ui__send_message_to_user", {"content": "Reply to Ann that Thursday works for you."}),
    _say("email__reply_to_email", {"email_id": "e_ann", "content": "Thursday works for me!"}),
    _say("agent_ui__send_message_to_user", {"content": "Replied to Ann: Thursday works."}),
    _say("system__wait"),
]


def assistant_server_requests(servers: tuple[FakeChatServer, FakeChatServer]) -> list[dict[str, Any]]:
    return servers[1].requests


def _play(
    servers: tuple[FakeChatServer, FakeChatServer],
    backend: str,
    user_script: list[Any],
    assistant_script: list[Any],
    *,
    cache: ModelCallCache | None = None,
    ledger: UsageLedger | None = None,
) -> EpisodeResult:
    user_server, assistant_server = servers
    user_server.push(*user_script)
    assistant_server.push(*assistant_script)
    user_model = ModelClient(_config(user_server, backend), role="user", cache=cache, ledger=ledger)
    assistant_model = ModelClient(
        _config(assistant_server, backend), role="observe", cache=cache, ledger=ledger
    )
    user = LLMUser(user_model, persona="Answers email quickly.")
    assistant = LLMAssistant(assistant_model)
    return run_episode(SCENARIO, user, assistant)


@pytest.mark.parametrize("backend", BACKENDS)
def test_proposal_acceptance_execution_and_checks(
    servers: tuple[FakeChatServer, FakeChatServer], backend: str
) -> None:
    ledger = UsageLedger()
    result = _play(servers, backend, USER_ACCEPTS, ASSISTANT_SCRIPT, ledger=ledger)
    assert result.success, result.outcome.failures()
    modes = [(s.turn, s.mode, s.action.tool) for s in result.steps if s.actor == "assistant"]
    assert (4, "execute", "email__reply_to_email") in modes
    first = next(s for s in result.steps if s.actor == "assistant")
    assert first.action.usage is not None and first.action.usage.calls == 2  # one malformed answer
    assert first.action.usage.format_errors[0].startswith("Your answer had no Action: section")
    assert "had no Action: section" in assistant_server_requests(servers)[1]["messages"][-1]["content"]
    user_server, assistant_server = servers
    # the prompts went out: system prompts of each role, the user's screen, the assistant's observation
    user_request = user_server.requests[1]["messages"]
    assert user_request[0]["role"] == "system" and "Answers email quickly." in user_request[0]["content"]
    assert "Current app" in user_request[-1]["content"] or "home screen" in user_request[-1]["content"]
    execute_request = assistant_server.requests[5]["messages"]
    assert "Reply to Ann that Thursday works for you." in execute_request[0]["content"]
    assert len(execute_request) == 2  # a fresh conversation for the task
    assert ledger.role("user").calls == 5 and ledger.role("observe").calls == 8
    assert ledger.cost_usd is not None and ledger.cost_usd > 0


@pytest.mark.parametrize("backend", BACKENDS)
def test_rejection_means_nothing_is_done_and_checks_fail(
    servers: tuple[FakeChatServer, FakeChatServer], backend: str
) -> None:
    user_rejects = [
        *USER_ACCEPTS[:3],
        _say("reject_proposal", {"reason": "Not now."}),
        _say("wait"),
        _say("wait"),
    ]
    assistant = [*ASSISTANT_SCRIPT[:5], _say("system__wait"), _say("system__wait")]
    result = _play(servers, backend, user_rejects, assistant)
    assert not result.success
    assert result.env.agent_ui.state.proposals[0].status == "rejected"
    assert not [s for s in result.steps if s.mode == "execute"]


def test_replay_from_the_cache_gives_the_same_trajectory(
    servers: tuple[FakeChatServer, FakeChatServer], tmp_path: Path
) -> None:
    path = tmp_path / "calls.sqlite"
    recorded = _play(
        servers, "openai", USER_ACCEPTS, ASSISTANT_SCRIPT, cache=ModelCallCache(path, "read_write")
    )
    requests = servers[0].count + servers[1].count
    replayed = _play(servers, "openai", [], [], cache=ModelCallCache(path, "replay"))
    assert servers[0].count + servers[1].count == requests  # nothing reached a server
    assert json.dumps(replayed.to_dict(), sort_keys=True) == json.dumps(recorded.to_dict(), sort_keys=True)
