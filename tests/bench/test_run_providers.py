"""The README's model setup (``pare run --user-model gpt-5-mini --assistant-model gpt-4o``) against servers
that answer as the providers do (:mod:`pare.testing.providers`), through the real clients.

Each test runs the README's command shape with ``--*-endpoint`` pointing at local
:class:`~pare.testing.ChatServer` s and checks that the run completes, what each request carried, the
warning a user sees, and the manifest's record of what was sent.
"""

from __future__ import annotations

import json
import logging
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

from pare.agents.models import litellm_available
from pare.cli import main
from pare.results.run_folder import MANIFEST, load_run
from pare.testing import (
    AnthropicChatServer,
    ChatServer,
    Reply,
    Responder,
    anthropic_messages,
    cached_prompts,
    context_limit,
    openai_reasoning,
    proactive_play,
    rate_limited,
    tool_calls_only,
)

KEY_VARIABLE = "PARE_TEST_API_KEY"
SCENARIO = "dentist_moves_checkup"
WITH_LITELLM = pytest.mark.skipif(not litellm_available(), reason="the litellm extra is not installed")
BACKENDS = ["openai", pytest.param("litellm", marks=WITH_LITELLM)]


@pytest.fixture(autouse=True)
def dummy_key(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv(KEY_VARIABLE, "sk-pare-dummy-key")
    for name in ("OPENAI_API_KEY", "ANTHROPIC_API_KEY", "OPENAI_BASE_URL"):
        monkeypatch.delenv(name, raising=False)


@pytest.fixture
def warnings(caplog: pytest.LogCaptureFixture) -> Iterator[pytest.LogCaptureFixture]:
    caplog.set_level(logging.WARNING, "pare.models")
    yield caplog


def readme_run(
    output: Path,
    user: ChatServer,
    assistant: ChatServer,
    *settings: str,
    backend: str = "openai",
    user_model: str = "gpt-5-mini",
    assistant_model: str = "gpt-4o",
) -> int:
    """``pare run -s dentist_moves_checkup --runs 1 --user-model M --assistant-model M`` at the servers."""
    prefix = "openai/" if backend == "litellm" else ""
    argv = ["run", "-s", SCENARIO, "--runs", "1", "--output", str(output), "--no-progress"]
    argv += ["--user-model", prefix + user_model, "--user-endpoint", user.base_url]
    argv += ["--assistant-model", prefix + assistant_model, "--assistant-endpoint", assistant.base_url]
    for role in ("user", "assistant"):
        argv += ["--set", f"models.{role}.retry_initial_s=0.001", "--set", f"models.{role}.retry_max_s=0.05"]
        if backend == "litellm":  # litellm's OpenAI client wants a key: a dummy one from the environment
            argv += [f"--{role}-provider", "litellm", "--set", f"models.{role}.api_key_env={KEY_VARIABLE}"]
        else:
            argv += ["--set", f"models.{role}.api_key_env=null"]
    return main(argv + list(settings))


def params_sent(server: ChatServer) -> list[dict[str, Any]]:
    """What each request carried besides the model, the conversation and the tools."""
    return [
        {k: v for k, v in body.items() if k not in ("model", "messages", "tools")} for body in server.requests
    ]


def manifest_requests(output: Path) -> dict[str, Any]:
    return dict(json.loads((output / MANIFEST).read_text(encoding="utf-8"))["requests"])


def warned(caplog: pytest.LogCaptureFixture, text: str) -> list[str]:
    return [r.getMessage() for r in caplog.records if r.name == "pare.models" and text in r.getMessage()]


def completed(output: Path) -> list[Any]:
    records = load_run(output).records
    assert len(records) == 1 and all(record.complete for record in records), records
    return records


@pytest.mark.parametrize("backend", BACKENDS)
def test_the_papers_setup_runs_against_openai_reasoning_rules(
    tmp_path: Path, backend: str, warnings: pytest.LogCaptureFixture
) -> None:
    with (
        ChatServer(openai_reasoning(proactive_play())) as user,
        ChatServer(openai_reasoning(proactive_play())) as assistant,
    ):
        settings = ("--set", "models.user.temperature=0.0", "--set", "models.user.max_tokens=2048")
        assert readme_run(tmp_path / "run", user, assistant, *settings, backend=backend) == 0
        completed(tmp_path / "run")
        requests_made = user.request_count
        # the same command resumes the run (its max_tokens is a setting, not a secret to mask): nothing new
        assert readme_run(tmp_path / "run", user, assistant, *settings, backend=backend) == 0
        assert user.request_count == requests_made
        # the reasoning model got its token limit under its own name and no temperature: never refused
        assert user.request_count > 0
        assert all(params == {"max_completion_tokens": 2048} for params in params_sent(user))
        # nothing configured for the chat model: nothing sent, the provider's defaults apply
        assert assistant.request_count > 0 and all(params == {} for params in params_sent(assistant))
    (warning,) = warned(warnings, "user model")[:1]
    assert "temperature=0.0" in warning and "not honoured" in warning
    requests = manifest_requests(tmp_path / "run")
    assert requests["user"]["sent"] == {"max_completion_tokens": 2048}
    assert requests["user"]["configured"] == {"temperature": 0.0, "max_tokens": 2048}
    assert [(a["param"], a["action"], a["learned"]) for a in requests["user"]["adjusted"]] == [
        ("temperature", "dropped", False),
        ("max_tokens", "renamed", False),
    ]
    assert (
        requests["observe"]
        == requests["execute"]
        == {
            "model": ("openai/" if backend == "litellm" else "") + "gpt-4o",
            "backend": backend,
            "configured": {},
            "sent": {},
            "adjusted": [],
        }
    )


def recording_manifest(responder: Responder, output: Path, seen: list[dict[str, Any]]) -> Responder:
    """``responder``, noting the manifest's record of the user's requests as each request arrives."""

    def respond(body: dict[str, Any]) -> Reply:
        if (output / MANIFEST).exists():
            seen.append(manifest_requests(output).get("user", {}))
        return responder(body)

    return respond


@pytest.mark.parametrize("backend", BACKENDS)
def test_a_refusal_by_name_is_learned_once_recorded_at_once_and_remembered_on_resume(
    tmp_path: Path, backend: str, warnings: pytest.LogCaptureFixture
) -> None:
    output = tmp_path / "run"
    seen: list[dict[str, Any]] = []
    # an Azure-style deployment name: PARE cannot know it is a reasoning model until the provider says so
    play = openai_reasoning(proactive_play(), reasoning=lambda model: model.endswith("paper-user"))
    with (
        ChatServer(recording_manifest(play, output, seen)) as user,
        ChatServer(proactive_play()) as assistant,
    ):
        # the judge (the user's model) would learn the refusal too, on its own: keep to the user's requests
        settings = ("--set", "models.user.temperature=0.0", "--set", "models.deterministic_judge=true")
        code = readme_run(output, user, assistant, *settings, backend=backend, user_model="paper-user")
        assert code == 0
        completed(output)
        sent = params_sent(user)
        # one failed round trip for the run, then never again
        assert sent[0] == {"temperature": 0.0} and all(params == {} for params in sent[1:])
        assert seen[1]["sent"] == {} and seen[1]["adjusted"][0]["learned"]  # recorded before the next call
        requests = manifest_requests(output)
        assert requests["user"]["sent"] == {}
        ((adjustment),) = requests["user"]["adjusted"]
        assert (adjustment["param"], adjustment["action"], adjustment["learned"]) == (
            "temperature",
            "dropped",
            True,
        )
        assert "unsupported_value" in adjustment["why"]
        assert len(warned(warnings, "user model")) == 1

        # a later session of the run (more runs) knows the refusal from the manifest: no round trip
        user.reset()
        more = (*settings, "--runs", "2")
        assert readme_run(output, user, assistant, *more, backend=backend, user_model="paper-user") == 0
        assert user.request_count > 0 and all(params == {} for params in params_sent(user))
    assert manifest_requests(output)["user"]["adjusted"] == [adjustment]


def test_rate_limits_are_waited_out(tmp_path: Path) -> None:
    with (
        ChatServer(rate_limited(proactive_play(), every=3)) as user,
        ChatServer(rate_limited(proactive_play(), every=2)) as assistant,
    ):
        assert readme_run(tmp_path / "run", user, assistant) == 0
        (record,) = completed(tmp_path / "run")
        calls = sum(usage.calls for usage in record.usage.values())
        assert user.request_count + assistant.request_count > calls  # some were refused and sent again
        assert all(usage.failed_calls == 0 for usage in record.usage.values())


@pytest.mark.parametrize("backend", BACKENDS)
def test_answers_with_only_tool_calls_play_through_native_tools(tmp_path: Path, backend: str) -> None:
    with (
        ChatServer(tool_calls_only(proactive_play())) as user,
        ChatServer(tool_calls_only(proactive_play())) as assistant,
    ):
        native = ("--set", "models.user.native_tools=true", "--set", "models.assistant.native_tools=true")
        assert readme_run(tmp_path / "run", user, assistant, *native, backend=backend) == 0
        (record,) = completed(tmp_path / "run")
        bodies = user.requests + assistant.requests
        assert all(body.get("tools") for body in bodies)
        # the answers were tool calls: the conversations carry them back, each answered by a tool message
        echoed = [m for body in bodies for m in body["messages"] if m["role"] == "assistant"]
        assert echoed and all(m.get("tool_calls") for m in echoed)
        assert any(m["role"] == "tool" for body in bodies for m in body["messages"])
    assert {p.decision for p in record.proposals} == {"accept"}


def test_cached_prompt_tokens_are_counted_and_priced(tmp_path: Path) -> None:
    with (
        ChatServer(cached_prompts(proactive_play(), share=0.5)) as user,
        ChatServer(proactive_play()) as assistant,
    ):
        prices = "models.user.prices={input: 1.0, output: 2.0, cached_input: 0.1}"
        assert readme_run(tmp_path / "run", user, assistant, "--set", prices) == 0
        (record,) = completed(tmp_path / "run")
    usage = record.usage["user"]
    # half of each call's prompt (rounded down) was served from the provider's cache
    assert usage.prompt_tokens // 2 - usage.calls <= usage.cached_tokens <= usage.prompt_tokens // 2
    full_price = (usage.prompt_tokens * 1.0 + usage.completion_tokens * 2.0) / 1e6
    assert usage.cost_usd is not None and usage.cost_usd < full_price


def test_a_prompt_beyond_the_context_is_the_models_failure_not_the_runs(tmp_path: Path) -> None:
    with (
        ChatServer(proactive_play()) as user,
        ChatServer(context_limit(proactive_play(), max_prompt_tokens=10)) as assistant,
    ):
        code = readme_run(tmp_path / "run", user, assistant)
        records = load_run(tmp_path / "run").records
        assert assistant.request_count > 0
    assert code == 0 and len(records) == 1 and records[0].complete
    assert not records[0].success


@WITH_LITELLM
def test_an_anthropic_user_through_litellm(tmp_path: Path, warnings: pytest.LogCaptureFixture) -> None:
    output = tmp_path / "run"
    with (
        AnthropicChatServer(anthropic_messages(proactive_play())) as user,
        ChatServer(proactive_play()) as assistant,
    ):
        argv = ["run", "-s", SCENARIO, "--runs", "1", "--output", str(output), "--no-progress"]
        argv += ["--user-provider", "litellm", "--user-model", "anthropic/claude-3-5-haiku-latest"]
        argv += [
            "--user-endpoint",
            user.anthropic_base_url,
            "--set",
            f"models.user.api_key_env={KEY_VARIABLE}",
        ]
        argv += ["--set", "models.user.seed=7", "--set", "models.user.temperature=0.2"]
        argv += ["--assistant-model", "gpt-4o", "--assistant-endpoint", assistant.base_url]
        argv += ["--set", "models.assistant.api_key_env=null"]
        assert main(argv) == 0
        completed(output)
        assert user.request_count > 0
        for body in user.requests:  # Anthropic takes no seed; its required max_tokens is litellm's default
            assert "seed" not in body and body["temperature"] == 0.2 and body["max_tokens"] > 0
    assert len(warned(warnings, "seed=7")) == 2  # once for the user, once for the judge (the user's model)
    assert manifest_requests(output)["user"]["sent"] == {"temperature": 0.2}


def test_refusals_learned_in_ray_tasks_reach_the_manifest(
    tmp_path: Path, warnings: pytest.LogCaptureFixture
) -> None:
    pytest.importorskip("ray", reason="Ray is an optional extra")
    output = tmp_path / "run"
    play = openai_reasoning(proactive_play(), reasoning=lambda model: model.endswith("paper-user"))
    with ChatServer(play) as user, ChatServer(proactive_play()) as assistant:
        settings = ("--set", "models.user.temperature=0.0", "--set", "models.deterministic_judge=true")
        ray = ("--backend", "ray", "--concurrency", "1")
        assert readme_run(output, user, assistant, *settings, *ray, user_model="paper-user") == 0
        completed(output)
        assert params_sent(user)[0] == {"temperature": 0.0}
    (adjustment,) = manifest_requests(output)["user"]["adjusted"]
    assert (adjustment["param"], adjustment["learned"]) == ("temperature", True)
    assert len(warned(warnings, "user model 'paper-user': temperature=0.0")) == 1  # told in the driver


def test_the_profiles_answer_in_the_providers_formats() -> None:
    def ok(body: dict[str, Any]) -> Reply:
        return Reply(200, {"choices": [{"message": {"role": "assistant", "content": "hi"}}], "usage": {}})

    reasoning = openai_reasoning(ok)
    refused = reasoning({"model": "gpt-5-mini", "temperature": 0.0})
    assert refused.status == 400
    assert (refused.body["error"]["param"], refused.body["error"]["code"]) == (
        "temperature",
        "unsupported_value",
    )
    assert reasoning({"model": "o4-mini", "max_tokens": 5}).body["error"]["code"] == "unsupported_parameter"
    assert (
        reasoning({"model": "o4-mini", "max_completion_tokens": 5, "reasoning_effort": "low"}).status == 200
    )
    assert reasoning({"model": "gpt-5-chat-latest", "temperature": 0.0}).status == 200
    assert (
        reasoning({"model": "gpt-4o", "reasoning_effort": "low"}).body["error"]["param"] == "reasoning_effort"
    )

    limited = rate_limited(ok, every=2, retry_after_ms=1500)
    first, second = limited({"model": "m"}), limited({"model": "m"})
    assert first.status == 200 and second.status == 429
    assert second.headers["Retry-After"] == "2" and second.headers["retry-after-ms"] == "1500"
    assert second.body["error"]["code"] == "rate_limit_exceeded"

    too_long = context_limit(ok, max_prompt_tokens=1)({"messages": [{"role": "user", "content": "x" * 40}]})
    assert (too_long.status, too_long.body["error"]["code"]) == (400, "context_length_exceeded")

    anthropic = anthropic_messages(ok)
    assert (
        anthropic({"model": "claude", "messages": []}).body["error"]["message"]
        == "max_tokens: Field required"
    )
    assert anthropic({"model": "claude", "max_tokens": 5, "seed": 1, "messages": []}).status == 400
    answer = anthropic({"model": "claude", "max_tokens": 5, "messages": [{"role": "user", "content": "x"}]})
    assert answer.body["content"] == [{"type": "text", "text": "hi"}] and answer.body["type"] == "message"
