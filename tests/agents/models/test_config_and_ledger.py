from __future__ import annotations

import json
import subprocess
import sys

import pytest
from pydantic import ValidationError

from pare.agents.models import ChatMessage, Completion, ModelConfig, Prices, RoleUsage, Usage, UsageLedger
from pare.errors import UserInputError


def test_defaults() -> None:
    config = ModelConfig(model="gpt-4o-mini")
    assert config.backend == "openai"
    assert config.api_key_env == "OPENAI_API_KEY"
    assert (config.temperature, config.max_tokens, config.seed, config.extra) == (None, None, None, {})
    assert config.request_params() == {}  # nothing is sent that is not configured: the provider's defaults
    assert ModelConfig(model="m", temperature=0.0, max_tokens=5).request_params() == {
        "temperature": 0.0,
        "max_tokens": 5,
    }
    assert (config.timeout_s, config.max_retries, config.retry_initial_s, config.retry_max_s) == (
        60,
        5,
        1.0,
        30.0,
    )
    assert (config.max_concurrency, config.prices, config.native_tools) == (16, None, False)
    assert ModelConfig(model="anthropic/claude-3-5-haiku-latest", backend="litellm").api_key_env is None
    assert ModelConfig(model="local", api_key_env=None).api_key_env is None


def test_config_rejects_what_it_does_not_know() -> None:
    with pytest.raises(ValidationError):
        ModelConfig(model="m", temprature=0.2)  # type: ignore[call-arg]
    with pytest.raises(ValidationError, match="use the configuration's own fields"):
        ModelConfig(model="m", extra={"temperature": 1.0})
    with pytest.raises(ValidationError, match="NAME of an environment variable"):
        ModelConfig(model="m", api_key_env="sk-abc123")
    with pytest.raises(ValidationError, match="retry_max_s"):
        ModelConfig(model="m", retry_initial_s=5, retry_max_s=1)
    with pytest.raises(ValidationError):
        ModelConfig(model="m", backend="anthropic")  # type: ignore[arg-type]
    with pytest.raises(ValidationError):
        ModelConfig(model="m").model_copy().__setattr__("model", "x")  # frozen


def test_parse_turns_validation_errors_into_user_input_errors() -> None:
    with pytest.raises(UserInputError, match=r"roles\.judge: max_concurrency: .*greater than or equal to 1"):
        ModelConfig.parse({"model": "m", "max_concurrency": 0}, where="roles.judge")
    assert ModelConfig.parse({"model": "m"}).model == "m"


def test_public_dict_holds_no_secret() -> None:
    config = ModelConfig(model="m", api_base="https://user:hunter2@llm.example:8443/v1?key=abc")
    public = config.public_dict()
    text = json.dumps(public)
    assert "hunter2" not in text and "abc" not in text
    assert public["api_base"] == "https://***@llm.example:8443/v1?***"
    assert public["api_key_env"] == "OPENAI_API_KEY"
    assert "hunter2" not in config.endpoint()


def test_prices() -> None:
    prices = Prices(input=2.0, output=8.0, cached_input=0.5)
    assert prices.cost(1000, 100, 400) == pytest.approx((600 * 2 + 400 * 0.5 + 100 * 8) / 1e6)
    assert Prices(input=2.0, output=8.0).cost(1000, 0, 400) == pytest.approx(1000 * 2 / 1e6)


def test_messages() -> None:
    assert ChatMessage.user("hi").to_openai() == {"role": "user", "content": "hi"}
    with pytest.raises(ValidationError, match="tool_call_id"):
        ChatMessage(role="tool", content="x")
    with pytest.raises(ValidationError, match="needs content"):
        ChatMessage(role="user")
    message = ChatMessage.model_validate_json(ChatMessage.tool("c1", "done").model_dump_json())
    assert message == ChatMessage.tool("c1", "done")


def completion(cost: float | None, *, cached: bool = False) -> Completion:
    return Completion(
        text="x",
        usage=Usage(prompt_tokens=10, completion_tokens=5, cached_tokens=2),
        cost_usd=cost,
        latency_s=0.5,
        model="m",
        from_cache=cached,
    )


def test_ledger_totals_per_role_and_unknown_cost() -> None:
    ledger = UsageLedger()
    ledger.record("user", completion(0.01))
    ledger.record("user", completion(0.02, cached=True))
    ledger.record("judge", completion(None))
    ledger.record_failure("judge")

    user = ledger.role("user")
    assert (
        user.calls,
        user.cached_calls,
        user.prompt_tokens,
        user.completion_tokens,
        user.cached_tokens,
    ) == (
        2,
        1,
        20,
        10,
        4,
    )
    assert user.latency_s == pytest.approx(1.0)
    assert user.cost_usd == pytest.approx(0.03)
    assert user.cached_cost_usd == pytest.approx(0.02)
    judge = ledger.role("judge")
    assert (judge.calls, judge.failed_calls, judge.unknown_cost_calls, judge.cost_usd) == (1, 1, 1, None)
    assert judge.describe_cost() == "unknown (1 of 1 calls unpriced)"

    total = ledger.total()
    assert total.calls == 3 and total.cost_usd is None and total.known_cost_usd == pytest.approx(0.03)
    assert ledger.cost_usd is None
    assert ledger.role("generator") == RoleUsage()

    summary = json.loads(json.dumps(ledger.summary()))
    assert list(summary["roles"]) == ["judge", "user"]
    assert summary["roles"]["judge"]["cost_usd"] is None
    assert summary["roles"]["user"]["cost_usd"] == pytest.approx(0.03)
    assert summary["total"]["cost"] == "unknown (1 of 3 calls unpriced; $0.0300 known)"
    assert summary["total"]["total_tokens"] == 45


def test_an_empty_ledger_costs_nothing_known() -> None:
    assert UsageLedger().cost_usd == 0.0
    assert UsageLedger().summary() == {"roles": {}, "total": RoleUsage().summary()}


def test_importing_pare_does_not_import_the_sdks() -> None:
    code = (
        "import sys, pare, pare.cli, pare.agents.models;"
        "print(sorted(m for m in ('openai', 'litellm', 'httpx') if m in sys.modules))"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert done.stdout.strip() == "[]"
