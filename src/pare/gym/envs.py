"""The Gymnasium environments: :mod:`pare.training.envs`'s asynchronous ones, stepped in an event loop of
their own.

Each environment owns a private event loop; ``reset`` and ``step`` run the asynchronous environment's
coroutine in it until it returns. Between calls the episode's task waits in that loop for the next action,
so no thread is needed and nothing polls. A synchronous environment cannot be used from inside a running
event loop (``asyncio.run`` cannot nest): there, await the asynchronous environments instead.
"""

from __future__ import annotations

import asyncio
import string
from collections.abc import Coroutine
from typing import Any, TypeVar

import gymnasium
from gymnasium import spaces

from pare.training.envs import AsyncProactiveAssistantEnv, AsyncUserEnv, StepResult

MAX_TEXT = 1_000_000
"""The longest observation or action a space holds, in characters (a system prompt is some 20,000)."""

_T = TypeVar("_T")


class TextSpace(spaces.Text):
    """Any text up to ``max_length`` characters, whatever its characters (Gymnasium's :class:`~gymnasium.
    spaces.Text` holds only those of its charset; phone screens hold any Unicode). Samples are drawn from
    printable ASCII.
    """

    def __init__(self, max_length: int = MAX_TEXT, *, min_length: int = 0) -> None:
        super().__init__(max_length, min_length=min_length, charset=string.printable)

    def contains(self, x: Any) -> bool:
        """Whether ``x`` is a string of an allowed length."""
        return isinstance(x, str) and self.min_length <= len(x) <= self.max_length


class _PareEnv(gymnasium.Env[str, str]):
    metadata: dict[str, Any] = {"render_modes": []}

    def __init__(self, core: AsyncProactiveAssistantEnv | AsyncUserEnv) -> None:
        self.core = core
        self.observation_space = TextSpace()
        self.action_space = TextSpace()
        self._loop = asyncio.new_event_loop()

    def _run(self, coroutine: Coroutine[Any, Any, _T]) -> _T:
        if self._loop.is_closed():
            coroutine.close()
            raise RuntimeError("the environment is closed")
        return self._loop.run_until_complete(coroutine)

    def reset(
        self, *, seed: int | None = None, options: dict[str, Any] | None = None
    ) -> tuple[str, dict[str, Any]]:
        """Start an episode (see :meth:`pare.training.envs.AsyncProactiveAssistantEnv.reset`); ``seed``
        seeds Gymnasium's generator, which draws the scenario and the world's seed.
        """
        super().reset(seed=seed)
        episode_seed = int(self.np_random.integers(2**63))
        return self._run(self.core.reset(seed=episode_seed, options=options))

    def step(self, action: str) -> StepResult:
        """Give the agent's action text (see :meth:`pare.training.envs.AsyncProactiveAssistantEnv.step`)."""
        return self._run(self.core.step(action))

    def close(self) -> None:
        """Stop the episode under way, close the counterpart's model clients and the event loop."""
        if self._loop.is_closed():
            return
        self._loop.run_until_complete(self.core.aclose())
        self._loop.close()


class ProactiveAssistantEnv(_PareEnv):
    """``pare/ProactiveAssistant-v0``: the agent plays the proactive assistant. Keyword arguments as
    :class:`~pare.training.envs.AsyncProactiveAssistantEnv` (``user``, ``scenarios`` or ``split``, ``reward``,
    ``protocol``, ...).
    """

    def __init__(self, render_mode: str | None = None, **kwargs: Any) -> None:
        super().__init__(AsyncProactiveAssistantEnv(**kwargs))
        self.render_mode = render_mode


class UserEnv(_PareEnv):
    """``pare/User-v0``: the agent plays the user. Keyword arguments as
    :class:`~pare.training.envs.AsyncUserEnv` (``assistant``, ``scenarios`` or ``split``, ``reward``, ...).
    """

    def __init__(self, render_mode: str | None = None, **kwargs: Any) -> None:
        super().__init__(AsyncUserEnv(**kwargs))
        self.render_mode = render_mode
