"""Settings of one environment (one episode's world)."""

from __future__ import annotations

from datetime import UTC, datetime

from pydantic import BaseModel, ConfigDict, Field

from pare.sim.notifications import NotificationPolicy

MAX_NOISE_RATE_PER_MINUTE = 60.0
"""The most distractor events per simulated minute (one a second): beyond it an episode drowns in noise
and its memory grows without bound."""


class WorldSettings(BaseModel):
    """The world's settings a benchmark run may change: the one declaration of them, which a run
    configuration's ``world`` takes as it is and :class:`EnvConfig` extends with what each episode sets.
    """

    model_config = ConfigDict(extra="forbid", frozen=True, allow_inf_nan=False)

    tool_failure_probability: float = Field(
        default=0.0, ge=0.0, le=1.0, description="Chance that an assistant app-tool call fails transiently."
    )
    noise_rate_per_minute: float = Field(
        default=0.0,
        ge=0.0,
        le=MAX_NOISE_RATE_PER_MINUTE,
        description="Distractor events per simulated minute (Poisson arrivals).",
    )
    notifications: NotificationPolicy = Field(default_factory=NotificationPolicy)

    def env_config(self, seed: int) -> EnvConfig:
        """One episode's world with these settings and environment seed ``seed``."""
        return EnvConfig(seed=seed, **{name: getattr(self, name) for name in WorldSettings.model_fields})


class EnvConfig(WorldSettings):
    """Everything that shapes an episode's world besides the scenario's data: the run's world settings,
    and what each episode sets (its seed, its start, how app bugs surface).
    """

    seed: int = Field(default=0, description="Seed of every random stream in the episode.")
    start_time: datetime = Field(default=datetime(2025, 1, 6, 9, 0, tzinfo=UTC))
    raise_internal_errors: bool = Field(
        default=False,
        description="Raise unexpected exceptions from app code instead of returning them as errors "
        "(for PARE's own tests; a benchmark run keeps going).",
    )
