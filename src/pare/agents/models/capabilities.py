"""Which request parameters a model accepts, and under which name, known before any request is sent.

OpenAI's reasoning models (the o-series: o1, o3, o4-mini, ...; the GPT-5 family except its chat models
such as ``gpt-5-chat-latest``) refuse every temperature but the default, ``top_p``, the penalties and
log-probabilities, and take ``max_completion_tokens`` instead of ``max_tokens``; OpenAI's chat models
refuse ``reasoning_effort``. With the litellm backend, litellm's own list of the OpenAI parameters each
provider supports (``litellm.get_supported_openai_params``) is consulted as well: Anthropic takes no
``seed``, for instance. Models this module does not know (a local vLLM model) are sent what is
configured; a refusal is then learned from the provider's answer (:mod:`pare.agents.models.refusals`).
"""

from __future__ import annotations

import re
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any, Literal

from pare.agents.models.config import ModelConfig

AdjustmentAction = Literal["renamed", "dropped"]

REASONING_REFUSED = (
    "temperature",
    "top_p",
    "presence_penalty",
    "frequency_penalty",
    "logprobs",
    "top_logprobs",
)
"""Sampling parameters OpenAI's reasoning models refuse (temperature: any value but the default 1)."""

RENAMED_FOR_REASONING = {"max_tokens": "max_completion_tokens"}
"""Parameters OpenAI's reasoning models take under another name."""

CHAT_REFUSED = ("reasoning_effort",)
"""Parameters OpenAI's chat (non-reasoning) models refuse."""

OPENAI_PARAMS = frozenset(
    {
        "temperature",
        "top_p",
        "max_tokens",
        "max_completion_tokens",
        "seed",
        "stop",
        "presence_penalty",
        "frequency_penalty",
        "logprobs",
        "top_logprobs",
        "logit_bias",
        "n",
        "reasoning_effort",
        "response_format",
        "parallel_tool_calls",
        "tool_choice",
        "user",
        "service_tier",
        "verbosity",
        "prediction",
        "modalities",
        "store",
    }
)
"""The OpenAI chat parameters litellm's supported-parameter lists speak about; other names in ``extra``
(a provider's own, such as vLLM's ``top_k``) are passed on untouched."""

_REASONING = re.compile(r"^(?:o[1-9]\d*(?:-.*)?|gpt-5(?:\.\d+)?(?:-.*)?)$")
_CHAT_VARIANT = re.compile(r"-chat(?:-|$)")
_OPENAI_CHAT = re.compile(r"^(?:gpt-4|gpt-3\.5|chatgpt-)")


@dataclass(frozen=True)
class Adjustment:
    """One configured parameter that a request carries under another name, or not at all."""

    param: str
    action: AdjustmentAction
    why: str
    to: str | None = None
    """The name it is sent under (``renamed`` only)."""
    learned: bool = False
    """Learned from the provider's refusal during the run, rather than known beforehand."""

    def to_json(self) -> dict[str, Any]:
        """The adjustment for the run's manifest."""
        data: dict[str, Any] = {"param": self.param, "action": self.action}
        if self.to is not None:
            data["to"] = self.to
        data["why"] = self.why
        data["learned"] = self.learned
        return data

    @classmethod
    def from_json(cls, data: Mapping[str, Any]) -> Adjustment:
        """The adjustment a manifest recorded (see :meth:`to_json`)."""
        action = data.get("action")
        if action not in ("renamed", "dropped") or not isinstance(data.get("param"), str):
            raise ValueError(f"not a recorded parameter adjustment: {dict(data)!r}")
        to = data.get("to")
        return cls(
            param=str(data["param"]),
            action="renamed" if action == "renamed" else "dropped",
            why=str(data.get("why", "")),
            to=str(to) if isinstance(to, str) else None,
            learned=bool(data.get("learned", False)),
        )


def bare_model_name(model: str) -> str:
    """The model's own name, without litellm's provider prefix (``openai/gpt-5-mini`` -> ``gpt-5-mini``)."""
    return model.rsplit("/", 1)[-1].strip().lower()


def is_reasoning_model(model: str) -> bool:
    """Whether ``model`` is one of OpenAI's reasoning models (o-series, GPT-5 family but its chat models)."""
    name = bare_model_name(model)
    return _REASONING.match(name) is not None and _CHAT_VARIANT.search(name) is None


def is_openai_chat_model(model: str) -> bool:
    """Whether ``model`` is one of OpenAI's chat models (GPT-4 and 3.5 families, GPT-5's chat models)."""
    name = bare_model_name(model)
    return _OPENAI_CHAT.match(name) is not None or (
        _REASONING.match(name) is not None and _CHAT_VARIANT.search(name) is not None
    )


def known_adjustments(config: ModelConfig) -> list[Adjustment]:
    """The adjustments this model needs to the parameters ``config`` sets, known before any request."""
    params = config.request_params()
    adjustments: list[Adjustment] = []
    if is_reasoning_model(config.model):
        for name in REASONING_REFUSED:
            if name not in params:
                continue
            if name == "temperature" and params[name] == 1:
                continue  # the default, which reasoning models accept
            only = " other than the default (1)" if name == "temperature" else ""
            adjustments.append(
                Adjustment(name, "dropped", f"OpenAI's reasoning models accept no {name}{only}")
            )
        for name, new_name in RENAMED_FOR_REASONING.items():
            if name in params and new_name not in params:
                adjustments.append(
                    Adjustment(name, "renamed", f"OpenAI's reasoning models take it as {new_name}", new_name)
                )
    elif is_openai_chat_model(config.model):
        adjustments.extend(
            Adjustment(name, "dropped", f"OpenAI's chat models accept no {name} (it is for reasoning models)")
            for name in CHAT_REFUSED
            if name in params
        )
    if config.backend == "litellm":
        adjusted = {adjustment.param for adjustment in adjustments}
        renamed = {a.to for a in adjustments if a.to is not None}
        supported = litellm_supported_params(config.model)
        if supported is not None:
            for name in [*params, *sorted(renamed)]:
                if name in OPENAI_PARAMS and name not in adjusted and name not in supported:
                    adjusted.add(name)
                    adjustments.append(
                        Adjustment(
                            name, "dropped", f"litellm lists no {name} among what {config.model} accepts"
                        )
                    )
    return adjustments


def litellm_supported_params(model: str) -> frozenset[str] | None:
    """The OpenAI parameters litellm says ``model`` accepts; ``None`` when litellm does not know."""
    from pare.agents.models.backends import import_litellm

    try:
        names = import_litellm().get_supported_openai_params(model=model)
    except Exception:  # litellm raises for a provider it cannot name: then it simply does not know
        return None
    return frozenset(str(name) for name in names) if names else None


def apply_adjustments(params: Mapping[str, Any], adjustments: list[Adjustment]) -> dict[str, Any]:
    """``params`` with each adjustment applied in order (a renamed parameter may be dropped later)."""
    sent = dict(params)
    for adjustment in adjustments:
        if adjustment.param not in sent:
            continue
        value = sent.pop(adjustment.param)
        if adjustment.action == "renamed" and adjustment.to is not None and adjustment.to not in sent:
            sent[adjustment.to] = value
    return sent
