from __future__ import annotations

from collections.abc import Callable, Iterable
from datetime import UTC, datetime
from typing import Any

import pytest

from pare.env import EnvConfig, Environment, ToolResult

START = datetime(2025, 3, 3, 9, 0, tzinfo=UTC)


def make_env(apps: Iterable[str] = (), seed_data: dict[str, Any] | None = None, **config: Any) -> Environment:
    """An environment with PARE's own invariants raised, not swallowed."""
    config.setdefault("start_time", START)
    env = Environment(list(apps), EnvConfig(raise_internal_errors=True, **config))
    if seed_data:
        env.load(seed_data)
    return env


def ok(result: ToolResult) -> Any:
    assert result.ok, result.error
    return result.value


def err(result: ToolResult, *fragments: str) -> str:
    assert not result.ok, f"expected an error, got {result.value!r}"
    assert result.error is not None
    for fragment in fragments:
        assert fragment.lower() in result.error.lower(), result.error
    return result.error


def screen_of(env: Environment) -> str | None:
    screen = env.system.current_screen()
    return None if screen is None else screen.screen_name()


@pytest.fixture
def env_factory() -> Callable[..., Environment]:
    return make_env


@pytest.fixture(autouse=True, scope="session")
def _private_scenario_cache(tmp_path_factory: pytest.TempPathFactory) -> None:
    """Tests read and write parsed scenarios in a cache of their own, never the user's."""
    import os

    os.environ["PARE_CACHE_DIR"] = str(tmp_path_factory.mktemp("pare-cache"))
