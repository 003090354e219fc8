"""A scripted model: answers from a list, for tests, demos and benchmarks that must not call a provider."""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from typing import Any

from pare.agents.models.types import ChatMessage, Completion, Usage
from pare.errors import UserInputError


class ScriptExhausted(UserInputError):
    """A scripted model was asked for more answers than its script holds."""


class ScriptedModel:
    """Answers each request with the next text of ``script`` (free, instant, deterministic).

    Records every conversation it was sent in :attr:`requests`. When the script runs out it answers
    ``fallback`` if one is given, else raises :class:`ScriptExhausted`.
    """

    def __init__(self, script: Iterable[str], *, fallback: str | None = None, name: str = "scripted") -> None:
        self.script = list(script)
        self.fallback = fallback
        self.name = name
        self.requests: list[list[ChatMessage]] = []

    async def complete(
        self, messages: Sequence[ChatMessage], tools: Sequence[dict[str, Any]] | None = None
    ) -> Completion:
        """The next scripted answer."""
        self.requests.append(list(messages))
        if self.script:
            text = self.script.pop(0)
        elif self.fallback is not None:
            text = self.fallback
        else:
            raise ScriptExhausted(
                f"scripted model '{self.name}' has no answer left for request {len(self.requests)}"
            )
        return Completion(text=text, usage=Usage(), cost_usd=0.0, latency_s=0.0, model=self.name)
