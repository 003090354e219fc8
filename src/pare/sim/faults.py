"""Tool-failure injection for robustness sweeps."""

from __future__ import annotations

import random

_TRANSIENT_ERRORS = (
    "503 Service Unavailable: the {app} service is temporarily unavailable. Please retry.",
    "504 Gateway Timeout: {app}.{tool} did not respond in time. Please retry.",
    "429 Too Many Requests: rate limit reached for {app}. Please retry in a moment.",
    "Connection reset by peer while calling {app}.{tool}. Please retry.",
    "502 Bad Gateway: upstream error in {app}. Please retry.",
    "500 Internal Server Error (transient) in {app}.{tool}. Please retry.",
    "Network unreachable: could not contact the {app} server. Please retry.",
)


class ToolFailureInjector:
    """Decides, from a seeded stream, whether an assistant's app-tool call fails with a transient error.

    The decision is one draw per eligible call, so the sequence of failures for a seed depends only on the
    sequence of eligible calls. Failing calls change nothing.
    """

    def __init__(self, probability: float, rng: random.Random) -> None:
        if not 0.0 <= probability <= 1.0:
            raise ValueError(f"tool failure probability must be within [0, 1], got {probability}")
        self.probability = probability
        self._rng = rng

    def draw(self, app: str, tool: str) -> str | None:
        """Return an error message when this call is to fail, else ``None``."""
        if self.probability <= 0.0:
            return None
        if self._rng.random() >= self.probability:
            return None
        template = self._rng.choice(_TRANSIENT_ERRORS)
        return "Transient error: " + template.format(app=app, tool=tool)
