"""`pare doctor`: one small call per configured role, through the real client, against local servers."""

from __future__ import annotations

import json
from collections.abc import Iterator
from typing import Any

import pytest

from pare.cli import main
from pare.testing import ChatServer, Reply, completion, failure, openai_reasoning

KEY = "PARE_DOCTOR_KEY"


def ready(body: dict[str, Any]) -> Reply:
    return completion("ready", 12, 1, model=str(body.get("model")))


@pytest.fixture(autouse=True)
def environment(monkeypatch: pytest.MonkeyPatch) -> None:
    for name in ("OPENAI_API_KEY", "OPENAI_BASE_URL", "PARE_GENERATOR_MODEL"):
        monkeypatch.delenv(name, raising=False)
    monkeypatch.setenv(KEY, "sk-doctor-dummy")


@pytest.fixture
def server() -> Iterator[ChatServer]:
    with ChatServer(ready) as running:
        yield running


def doctor_json(capsys: pytest.CaptureFixture[str], *args: str) -> tuple[int, list[dict[str, Any]]]:
    code = main(["doctor", *args, "--format", "json"])
    out = capsys.readouterr().out
    return code, json.loads(out)


def keyed(role: str) -> list[str]:
    return ["--set", f"models.{role}.api_key_env={KEY}"]


def test_each_distinct_model_is_called_once_and_reported_for_its_roles(
    server: ChatServer, capsys: pytest.CaptureFixture[str]
) -> None:
    code, checks = doctor_json(
        capsys,
        *("--user-model", "user-llm", "--user-endpoint", server.base_url, *keyed("user")),
        *("--assistant-model", "assistant-llm", "--assistant-endpoint", server.base_url, *keyed("assistant")),
    )
    assert code == 0
    # The judge is the user's model and observe/execute are the assistant's: two calls, not four.
    assert sorted(body["model"] for body in server.requests) == ["assistant-llm", "user-llm"]
    by_model = {check["model"]: check for check in checks}
    assert by_model["user-llm"]["roles"] == ["user", "judge"]
    assert by_model["assistant-llm"]["roles"] == ["observe", "execute"]
    user = by_model["user-llm"]
    assert user["ok"] and user["answer"] == "ready" and user["answered_by"] == "user-llm"
    assert user["tokens"] == {"prompt": 12, "completion": 1, "cached": 0}
    assert user["key"] == {"variable": KEY, "found": True}
    assert user["sent"] == {}  # nothing is sent that the configuration does not set
    assert "sk-doctor-dummy" not in json.dumps(checks)


def test_what_is_sent_is_what_the_run_would_send(
    server: ChatServer, capsys: pytest.CaptureFixture[str]
) -> None:
    code, (check,) = doctor_json(
        capsys,
        *("--user-model", "user-llm", "--user-endpoint", server.base_url, *keyed("user")),
        *("--set", "models.user.temperature=0.3", "--set", "models.user.max_tokens=64"),
    )
    assert code == 0
    assert check["sent"] == {"temperature": 0.3, "max_tokens": 64}
    (body,) = server.requests
    assert body["temperature"] == 0.3 and body["max_tokens"] == 64


def test_a_reasoning_model_s_refusals_are_shown_as_adjustments(capsys: pytest.CaptureFixture[str]) -> None:
    # A model the table does not know as a reasoning model, behind a server that refuses as OpenAI does
    # for reasoning models: the first call is refused, the parameter learned, the call sent again.
    with ChatServer(openai_reasoning(ready, reasoning=lambda name: True)) as strict:
        code, (check,) = doctor_json(
            capsys,
            *("--user-model", "house-reasoner", "--user-endpoint", strict.base_url, *keyed("user")),
            *("--set", "models.user.temperature=0.0", "--set", "models.user.max_tokens=64"),
            "--set",
            "models.deterministic_judge=true",
        )
        bodies = strict.requests
    assert code == 0, check
    assert check["ok"]
    assert "temperature" not in bodies[-1] and bodies[-1]["max_completion_tokens"] == 64
    assert check["sent"] == {"max_completion_tokens": 64}
    adjusted = {item["param"]: item for item in check["adjustments"]}
    assert adjusted["temperature"]["action"] == "dropped" and adjusted["temperature"]["learned"]
    assert adjusted["max_tokens"]["to"] == "max_completion_tokens"


def test_a_refused_key_fails_with_what_to_change(capsys: pytest.CaptureFixture[str]) -> None:
    def refuse(body: dict[str, Any]) -> Reply:
        return failure(401, "Incorrect API key provided", code="invalid_api_key")

    with ChatServer(refuse) as locked:
        code = main(
            ["doctor", "--user-model", "user-llm", "--user-endpoint", locked.base_url, *keyed("user")]
        )
    out = " ".join(capsys.readouterr().out.split())
    assert code == 1
    assert "FAIL user + judge: user-llm" in out
    assert f"Set {KEY} to a valid key" in out
    assert "1 of 1 model setting(s) failed" in out


def test_a_missing_key_is_reported_without_a_request(
    server: ChatServer, capsys: pytest.CaptureFixture[str]
) -> None:
    code, (check,) = doctor_json(
        capsys,
        "--user-model",
        "user-llm",
        "--user-endpoint",
        server.base_url,
        "--set",
        "models.user.api_key_env=NO_SUCH_KEY",
    )
    assert code == 1
    assert server.request_count == 0
    assert check["key"] == {"variable": "NO_SUCH_KEY", "found": False}
    assert check["failure"]["kind"] == "missing_api_key"
    assert "export NO_SUCH_KEY=" in check["failure"]["problem"]


def test_the_generator_is_checked_as_pare_generate_would_call_it(
    server: ChatServer, capsys: pytest.CaptureFixture[str]
) -> None:
    code, (check,) = doctor_json(
        capsys, "--generator-model", "writer-llm", "--generator-endpoint", server.base_url
    )
    assert code == 0
    assert check["roles"] == ["generator"]
    (body,) = server.requests
    assert body["model"] == "writer-llm" and body["temperature"] == 0.7  # the generator's usual setting


def test_the_text_report_names_each_role_and_what_was_sent(
    server: ChatServer, capsys: pytest.CaptureFixture[str]
) -> None:
    code = main(["doctor", "--user-model", "user-llm", "--user-endpoint", server.base_url, *keyed("user")])
    out = capsys.readouterr().out
    assert code == 0
    assert "ok    user + judge: user-llm at " + server.base_url in out
    assert "sent: no sampling parameter (the provider's defaults)" in out
    assert "tokens: 12 in, 1 out; price: unknown" in out
    assert "every model answered (1 checked)." in out


def test_nothing_configured_says_so(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["doctor"]) == 0
    assert "nothing to check" in capsys.readouterr().out
