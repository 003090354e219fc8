"""One small call per configured role, to learn before a run whether each model answers as configured.

:func:`check_roles` sends each distinct model configuration one short request through the same client a
run uses (the same request parameters, adjusted the same way, the same key variable and endpoint), with
the cache off and at most one retry, and reports per role what was sent and whether it was accepted, the
latency, the tokens, the price and, for a failure, what to change. Roles with the same configuration (the
assistant's observe and execute modes, a judge taken from the user) share one call.
"""

from __future__ import annotations

import asyncio
import os
import time
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

from pare.agents.models.client import ModelClient
from pare.agents.models.config import ModelConfig
from pare.agents.models.pricing import price_source
from pare.agents.models.secrets import redact_secrets
from pare.agents.models.types import ChatMessage
from pare.errors import ModelRequestError, ProviderUnavailable

PROBE = (
    ChatMessage.system("You are answering a connection check. Keep your answer to one word."),
    ChatMessage.user("Reply with the single word: ready"),
)
"""The request each role is sent: short, so it costs a fraction of a cent on any priced model."""

PROBE_RETRIES = 1
"""Retries of a transient failure: enough to ride out one blip, few enough to answer quickly."""


@dataclass(frozen=True)
class RoleCheck:
    """What one configuration's call showed, for every role that uses that configuration."""

    roles: tuple[str, ...]
    model: str
    backend: str
    endpoint: str
    key_variable: str | None
    key_found: bool | None
    """Whether the key's variable is set (``None``: no variable is named, none is needed or litellm finds
    the provider's own)."""
    ok: bool
    configured: dict[str, Any] = field(default_factory=dict)
    sent: dict[str, Any] = field(default_factory=dict)
    adjustments: list[dict[str, Any]] = field(default_factory=list)
    latency_s: float | None = None
    prompt_tokens: int | None = None
    completion_tokens: int | None = None
    cached_tokens: int | None = None
    answered_by: str | None = None
    answer: str | None = None
    reasoning: bool = False
    price_source: str | None = None
    cost_usd: float | None = None
    failure_kind: str | None = None
    problem: str | None = None
    """For a failure: what went wrong and what to change, as the run would say it."""

    def to_json(self) -> dict[str, Any]:
        """The check as JSON (``pare doctor --format json``)."""
        return {
            "roles": list(self.roles),
            "model": self.model,
            "backend": self.backend,
            "endpoint": self.endpoint,
            "key": {"variable": self.key_variable, "found": self.key_found},
            "ok": self.ok,
            "configured": self.configured,
            "sent": self.sent,
            "adjustments": self.adjustments,
            "latency_s": self.latency_s,
            "tokens": {
                "prompt": self.prompt_tokens,
                "completion": self.completion_tokens,
                "cached": self.cached_tokens,
            },
            "answered_by": self.answered_by,
            "answer": self.answer,
            "reasoning": self.reasoning,
            "price_source": self.price_source,
            "cost_usd": self.cost_usd,
            "failure": None if self.ok else {"kind": self.failure_kind, "problem": self.problem},
        }


def group_roles(roles: Mapping[str, ModelConfig]) -> list[tuple[tuple[str, ...], ModelConfig]]:
    """The distinct configurations among ``roles``, each with the roles that use it, in ``roles``' order."""
    groups: dict[str, tuple[list[str], ModelConfig]] = {}
    for role, config in roles.items():
        names, _ = groups.setdefault(config.model_dump_json(), ([], config))
        names.append(role)
    return [(tuple(names), config) for names, config in groups.values()]


async def check_roles(roles: Mapping[str, ModelConfig]) -> list[RoleCheck]:
    """Send one probe per distinct configuration in ``roles`` (concurrently) and report each."""
    groups = group_roles(roles)
    return list(await asyncio.gather(*(check_one(names, config) for names, config in groups)))


async def check_one(roles: tuple[str, ...], config: ModelConfig) -> RoleCheck:
    """Send ``config``'s model the probe, as the first of ``roles`` would, and report what happened."""
    quick = config.model_copy(update={"max_retries": min(config.max_retries, PROBE_RETRIES)})
    client = ModelClient(quick, role=roles[0])
    variable = config.api_key_env
    base = {
        "roles": roles,
        "model": config.model,
        "backend": config.backend,
        "endpoint": config.endpoint(),
        "key_variable": variable,
        "key_found": bool(os.environ.get(variable, "").strip()) if variable else None,
        "configured": redact_secrets(client.params.configured),
        "price_source": price_source(config),
    }
    started = time.perf_counter()
    try:
        completion = await client.complete(list(PROBE))
    except (ModelRequestError, ProviderUnavailable) as error:
        kind = error.kind if isinstance(error, ModelRequestError) else "unavailable"
        return RoleCheck(
            **base,
            ok=False,
            sent=redact_secrets(client.sent_params()),
            adjustments=[adjustment.to_json() for adjustment in client.adjustments],
            latency_s=time.perf_counter() - started,
            failure_kind=kind,
            problem=str(error),
        )
    finally:
        await client.aclose()
    text = " ".join(completion.text.split())
    return RoleCheck(
        **base,
        ok=True,
        sent=redact_secrets(client.sent_params()),
        adjustments=[adjustment.to_json() for adjustment in client.adjustments],
        latency_s=completion.latency_s,
        prompt_tokens=completion.usage.prompt_tokens,
        completion_tokens=completion.usage.completion_tokens,
        cached_tokens=completion.usage.cached_tokens,
        answered_by=completion.model,
        answer=text if len(text) <= 60 else text[:57] + "...",
        reasoning=bool(completion.reasoning),
        cost_usd=completion.cost_usd,
    )
