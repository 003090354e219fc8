"""What one ``pare generate`` batch is: the apps and aims, the generator and judge models, the limits."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from pydantic import BaseModel, ConfigDict, Field, ValidationError, field_validator

from pare.agents.models.cache import CacheMode
from pare.agents.models.capabilities import is_reasoning_model
from pare.agents.models.config import ModelConfig
from pare.apps.registry import CORE_APPS, app_names
from pare.errors import UserInputError, did_you_mean
from pare.scenarios.model import TAGS, Difficulty, Tag

IDENTITY_FIELDS = ("apps", "tags", "difficulty", "stage_retries")
"""The settings that shape what a candidate becomes; an output folder keeps them for good."""
MODEL_IDENTITY_FIELDS = ("model", "backend", "temperature", "max_tokens", "seed", "extra")
"""The fields of a model configuration that can change what it answers."""
GENERATOR_TEMPERATURE = 0.7
"""The generator's temperature unless one is given (reasoning models are sent none: they accept only
their own)."""


class GenerateConfig(BaseModel):
    """Everything one generation batch needs."""

    model_config = ConfigDict(extra="forbid", frozen=True, allow_inf_nan=False)

    apps: list[str] = Field(min_length=1, description="The apps every candidate must use.")
    tags: list[Tag] = Field(
        default_factory=list, description="Capability tags to aim at (cycled over the candidates)."
    )
    difficulty: list[Difficulty] = Field(
        default_factory=list, description="Difficulties allowed (cycled over the candidates)."
    )
    count: int = Field(
        default=1, ge=1, le=10_000, description="Candidates in the folder, finished ones included."
    )
    output: str = Field(min_length=1, description="The folder candidates, transcripts and the report go to.")
    generator: ModelConfig = Field(description="The model that writes the candidates.")
    judge: ModelConfig | None = Field(
        default=None, description="The uniqueness judge; none: the generator's model."
    )
    stage_retries: int = Field(
        default=3, ge=0, le=20, description="Times a stage's answer is sent back with its problems."
    )
    concurrency: int = Field(default=4, ge=1, le=256, description="Candidates in flight at once.")
    cache: CacheMode = Field(default="read_write", description="Model-call cache: off, read_write, replay.")
    library: list[str] = Field(
        default_factory=list,
        description="Scenario files or folders to compare with and take the example from; default the "
        "shipped library.",
    )
    prefilter: float = Field(
        default=0.3,
        ge=0.0,
        le=1.0,
        description="Story similarity (pare scenarios similar's measure, without tools) from which the "
        "judge is asked whether a candidate retells a library story.",
    )
    neighbours: int = Field(default=3, ge=1, le=20, description="Nearest library stories shown to the judge.")

    @field_validator("apps")
    @classmethod
    def _known_apps(cls, value: list[str]) -> list[str]:
        known = app_names()
        for app in value:
            if app in CORE_APPS:
                raise ValueError(f"'{app}' is on every phone; name the other apps")
            if app not in known:
                raise ValueError(f"unknown app '{app}'.{did_you_mean(app, known)} Apps: {', '.join(known)}")
        return list(dict.fromkeys(value))

    @property
    def judge_model(self) -> ModelConfig:
        """The judge's model configuration: the generator's model at temperature 0 (reasoning models: at
        their own, the only one they accept) unless one is given.
        """
        if self.judge is not None:
            return self.judge
        temperature = None if is_reasoning_model(self.generator.model) else 0.0
        return self.generator.model_copy(update={"temperature": temperature})

    @property
    def folder(self) -> Path:
        """The output folder."""
        return Path(self.output)

    def focus(self, index: int) -> tuple[str, str | None]:
        """The capability tag and difficulty candidate ``index`` (from 1) aims at."""
        tags = self.tags or list(TAGS)
        tag = tags[(index - 1) % len(tags)]
        difficulty = self.difficulty[(index - 1) % len(self.difficulty)] if self.difficulty else None
        return tag, difficulty

    def identity(self) -> dict[str, Any]:
        """What shapes the candidates, as JSON: kept in the folder and checked when a batch resumes."""
        models = {"generator": self.generator, "judge": self.judge_model}
        return {
            **{name: getattr(self, name) for name in IDENTITY_FIELDS},
            "models": {
                role: {k: v for k, v in config.public_dict().items() if k in MODEL_IDENTITY_FIELDS}
                for role, config in models.items()
            },
        }

    def public_dict(self) -> dict[str, Any]:
        """Every setting as JSON, endpoints without credentials (for the folder's manifest)."""
        data = self.model_dump(mode="json")
        data["generator"] = self.generator.public_dict()
        data["judge"] = self.judge_model.public_dict()
        return data


def build_generate_config(data: dict[str, Any]) -> GenerateConfig:
    """Validate ``data``, listing every problem with its setting."""
    try:
        return GenerateConfig.model_validate(data)
    except ValidationError as error:
        problems = "\n".join(
            f"  {'.'.join(str(p) for p in e['loc']) or '(top level)'}: "
            + str(e["msg"]).removeprefix("Value error, ")
            for e in error.errors()
        )
        raise UserInputError(f"not a valid generation configuration:\n{problems}") from None
