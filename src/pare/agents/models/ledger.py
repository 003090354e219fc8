"""Tokens, latency and cost per role, summed over the calls of a run or an episode."""

from __future__ import annotations

import threading
from typing import Any

from pydantic import BaseModel, ConfigDict, Field

from pare.agents.models.types import Completion


class RoleUsage(BaseModel):
    """Totals over one role's calls (or over every role's).

    Calls replayed from the record/replay cache count like the recorded calls they replay (same tokens,
    latency and cost), so a replayed run reports the same usage as the run it reproduces;
    ``cached_calls`` and ``cached_cost_usd`` say how much of it was not spent again.
    """

    model_config = ConfigDict(extra="forbid", frozen=True)

    calls: int = 0
    cached_calls: int = 0
    failed_calls: int = Field(default=0, description="Calls that raised (provider down, refused request).")
    prompt_tokens: int = 0
    completion_tokens: int = 0
    cached_tokens: int = Field(
        default=0, description="Prompt tokens served from the provider's prompt cache."
    )
    latency_s: float = 0.0
    known_cost_usd: float = Field(default=0.0, description="Sum of the costs that are known.")
    unknown_cost_calls: int = Field(default=0, description="Calls whose cost is unknown.")
    cached_cost_usd: float = Field(default=0.0, description="Known cost of the calls replayed from cache.")

    @property
    def cost_usd(self) -> float | None:
        """The total cost, or ``None`` ("unknown") when any call's cost is unknown; never 0 for unknown."""
        return None if self.unknown_cost_calls else self.known_cost_usd

    @property
    def total_tokens(self) -> int:
        """Prompt plus completion tokens."""
        return self.prompt_tokens + self.completion_tokens

    def add(self, completion: Completion) -> RoleUsage:
        """Return these totals with one more call."""
        cost = completion.cost_usd
        return self.model_copy(
            update={
                "calls": self.calls + 1,
                "cached_calls": self.cached_calls + int(completion.from_cache),
                "prompt_tokens": self.prompt_tokens + completion.usage.prompt_tokens,
                "completion_tokens": self.completion_tokens + completion.usage.completion_tokens,
                "cached_tokens": self.cached_tokens + completion.usage.cached_tokens,
                "latency_s": self.latency_s + completion.latency_s,
                "known_cost_usd": self.known_cost_usd + (cost or 0.0),
                "unknown_cost_calls": self.unknown_cost_calls + int(cost is None),
                "cached_cost_usd": self.cached_cost_usd + ((cost or 0.0) if completion.from_cache else 0.0),
            }
        )

    def __add__(self, other: RoleUsage) -> RoleUsage:
        return RoleUsage.model_validate(
            {name: getattr(self, name) + getattr(other, name) for name in RoleUsage.model_fields}
        )

    def summary(self) -> dict[str, Any]:
        """Return the totals as JSON, with ``cost_usd`` null when unknown and a readable ``cost``."""
        data = self.model_dump(mode="json")
        data["total_tokens"] = self.total_tokens
        data["cost_usd"] = self.cost_usd
        data["cost"] = self.describe_cost()
        return data

    def describe_cost(self) -> str:
        """Say the cost in words: ``'$0.0123'`` or ``'unknown (2 of 5 calls unpriced; $0.0040 known)'``."""
        if not self.unknown_cost_calls:
            return f"${self.known_cost_usd:.4f}"
        priced = self.calls - self.unknown_cost_calls
        known = f"; ${self.known_cost_usd:.4f} known" if priced else ""
        return f"unknown ({self.unknown_cost_calls} of {self.calls} calls unpriced{known})"


class StepUsage(BaseModel):
    """The model calls behind one action of one actor (kept with the step in the trajectory): how many,
    their tokens and cost, and the malformed answers that were sent back with a hint before the action.
    """

    model_config = ConfigDict(extra="forbid", frozen=True, allow_inf_nan=False)

    calls: int = Field(default=0, ge=0)
    prompt_tokens: int = Field(default=0, ge=0)
    completion_tokens: int = Field(default=0, ge=0)
    cached_tokens: int = Field(default=0, ge=0)
    cost_usd: float | None = Field(default=0.0, description="``None`` when any call's price is unknown.")
    format_errors: tuple[str, ...] = Field(default=(), description="Why each malformed answer was refused.")

    @property
    def tokens(self) -> int:
        """Prompt plus completion tokens."""
        return self.prompt_tokens + self.completion_tokens

    @property
    def cost_text(self) -> str:
        """The cost in words: ``$0.0123``, or ``unknown`` when any call had no price."""
        return "unknown" if self.cost_usd is None else f"${self.cost_usd:.4f}"

    def __add__(self, other: StepUsage) -> StepUsage:
        cost = None if self.cost_usd is None or other.cost_usd is None else self.cost_usd + other.cost_usd
        return StepUsage(
            calls=self.calls + other.calls,
            prompt_tokens=self.prompt_tokens + other.prompt_tokens,
            completion_tokens=self.completion_tokens + other.completion_tokens,
            cached_tokens=self.cached_tokens + other.cached_tokens,
            cost_usd=cost,
            format_errors=self.format_errors + other.format_errors,
        )


class UsageLedger:
    """Per-role usage of every model call made through the clients that share this ledger.

    Safe to share between asyncio tasks and threads (updates hold a lock and replace immutable totals).
    """

    def __init__(self) -> None:
        self._lock = threading.Lock()
        self._roles: dict[str, RoleUsage] = {}

    def record(self, role: str, completion: Completion) -> None:
        """Count one successful call (live or replayed from cache) for ``role``."""
        with self._lock:
            self._roles[role] = self._roles.get(role, RoleUsage()).add(completion)

    def record_failure(self, role: str) -> None:
        """Count one call of ``role`` that raised."""
        with self._lock:
            usage = self._roles.get(role, RoleUsage())
            self._roles[role] = usage.model_copy(update={"failed_calls": usage.failed_calls + 1})

    def role(self, role: str) -> RoleUsage:
        """Return the totals of one role (zeros when it made no call)."""
        with self._lock:
            return self._roles.get(role, RoleUsage())

    def roles(self) -> dict[str, RoleUsage]:
        """Return the totals of every role that made a call, by role name."""
        with self._lock:
            return dict(sorted(self._roles.items()))

    def total(self) -> RoleUsage:
        """Return the totals over every role."""
        total = RoleUsage()
        for usage in self.roles().values():
            total = total + usage
        return total

    @property
    def cost_usd(self) -> float | None:
        """The run's cost, or ``None`` ("unknown") when any call's cost is unknown."""
        return self.total().cost_usd

    def summary(self) -> dict[str, Any]:
        """Return ``{"roles": {role: totals}, "total": totals}`` as JSON-serialisable data."""
        return {
            "roles": {role: usage.summary() for role, usage in self.roles().items()},
            "total": self.total().summary(),
        }
