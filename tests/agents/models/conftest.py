from __future__ import annotations

from collections.abc import Callable, Iterator
from typing import Any

import pytest

from pare.agents.models import ModelConfig, litellm_available

from .fake_server import FakeChatServer

KEY_VARIABLE = "PARE_TEST_API_KEY"
KEY = "sk-test-not-a-real-key"

BACKENDS = [
    "openai",
    pytest.param(
        "litellm",
        marks=pytest.mark.skipif(not litellm_available(), reason="the litellm extra is not installed"),
    ),
]


@pytest.fixture
def server() -> Iterator[FakeChatServer]:
    fake = FakeChatServer().start()
    try:
        yield fake
    finally:
        fake.stop()


@pytest.fixture(autouse=True)
def api_key(monkeypatch: pytest.MonkeyPatch) -> str:
    monkeypatch.setenv(KEY_VARIABLE, KEY)
    # Nothing in these tests may fall back on a real key from the developer's environment.
    for name in ("OPENAI_API_KEY", "OPENAI_BASE_URL", "ANTHROPIC_API_KEY", "LITELLM_API_BASE"):
        monkeypatch.delenv(name, raising=False)
    return KEY


ConfigFactory = Callable[..., ModelConfig]


@pytest.fixture
def make_config(server: FakeChatServer) -> ConfigFactory:
    """A configuration pointing at the fake server, with tiny retry waits so tests stay fast."""

    def make(backend: str = "openai", model: str = "pare-test-model", **overrides: Any) -> ModelConfig:
        settings: dict[str, Any] = {
            "model": f"openai/{model}" if backend == "litellm" else model,
            "backend": backend,
            "api_base": server.base_url,
            "api_key_env": KEY_VARIABLE,
            "timeout_s": 5.0,
            "max_retries": 3,
            "retry_initial_s": 0.001,
            "retry_max_s": 0.01,
        }
        settings.update(overrides)
        return ModelConfig(**settings)

    return make
