"""The price of one call: prices from the configuration, else litellm's price table, else unknown."""

from __future__ import annotations

from typing import Literal

from pare.agents.models.backends import import_litellm, litellm_available
from pare.agents.models.config import ModelConfig
from pare.agents.models.types import Usage

PriceSource = Literal["config", "litellm"]


def call_cost(config: ModelConfig, usage: Usage, *, usage_reported: bool = True) -> float | None:
    """Return the call's price in USD, or ``None`` when it cannot be known (never 0 for unknown).

    Prices written in the configuration win: they are the person's explicit statement (a negotiated
    rate, a self-hosted model that litellm would price as a hosted one). Otherwise litellm's price table
    is used when litellm is installed and knows the model. A provider that reported no usage gives an
    unknown cost.
    """
    if not usage_reported:
        return None
    if config.prices is not None:
        return config.prices.cost(usage.prompt_tokens, usage.completion_tokens, usage.cached_tokens)
    return litellm_cost(config.model, usage)


def price_source(config: ModelConfig) -> PriceSource | None:
    """Say where the prices of ``config``'s model come from, or ``None`` when they are unknown."""
    if config.prices is not None:
        return "config"
    if litellm_cost(config.model, Usage(prompt_tokens=1_000_000, completion_tokens=1_000_000)) is not None:
        return "litellm"
    return None


def litellm_cost(model: str, usage: Usage) -> float | None:
    """Price the call with litellm's table; ``None`` when litellm is missing or does not know the model."""
    if not litellm_available():
        return None
    litellm = import_litellm()
    try:
        usage_object = litellm.Usage(
            prompt_tokens=usage.prompt_tokens,
            completion_tokens=usage.completion_tokens,
            total_tokens=usage.total_tokens,
            prompt_tokens_details={"cached_tokens": usage.cached_tokens},
        )
        prompt_cost, completion_cost = litellm.cost_per_token(
            model=model,
            prompt_tokens=usage.prompt_tokens,
            completion_tokens=usage.completion_tokens,
            usage_object=usage_object,
        )
    except Exception:  # litellm raises a variety of errors for models it does not map
        return None
    return float(prompt_cost) + float(completion_cost)
