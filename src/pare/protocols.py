"""Protocol presets: named sets of the turn protocol's settings, and a run's protocol as a preset plus
explicit overrides.

``pare`` is PARE's protocol (the defaults declared in :class:`~pare.sim.budget.TurnBudget`); ``paper``
follows the paper as closely as it specifies its protocol: proposals never expire, the user's prompt
judges proposals in the appendix's words, and a malformed model answer costs one of the 1 / 5 / 10
actions instead of being sent back outside them. The paper's definitions of the metrics (the proposal
rate over all turns) are chosen by the preset's name, which the manifest records. Every difference is
listed, with why and how much it moves, in ``docs/paper-conformance.md``.

In a run file, ``protocol: {preset: paper, max_turns: 20}`` takes the paper's protocol with 20 turns; the
fields given beside the preset are its overrides, recorded in the manifest and shown in reports.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any, Literal

from pydantic import Field, ValidationError, field_validator, model_validator

from pare.errors import did_you_mean
from pare.scenarios.times import TimeFormatError, parse_duration
from pare.sim.budget import TurnBudget

PresetName = Literal["pare", "paper"]

DEFAULT_PRESET: PresetName = "pare"

FORMAT_RETRIES = 2
"""PARE's default: times a malformed model answer is sent back within one step."""

PRESETS: dict[str, dict[str, Any]] = {
    "pare": {},
    "paper": {
        # The paper's proposals wait for an answer until the session ends.
        "proposal_ttl_turns": None,
        # The appendix's user prompt: "You have to be EXTREMELY STRICT about accepting proposals".
        "user_prompt": "paper",
        # The paper's agents take 1 / 5 / 10 iterations a turn; a malformed answer is one of them.
        "max_format_retries": 0,
    },
}
"""Each preset as the settings in which it differs from PARE's defaults."""

LEGACY_IDENTITY_FIELDS = frozenset(
    {
        "max_turns",
        "user_steps",
        "observe_steps",
        "execute_steps",
        "proposal_ttl_turns",
        "turn_duration",
        "max_format_retries",
    }
)
"""The protocol settings a run configuration had before presets: always in a run's identity. Settings
added since enter it only when they differ from PARE's default, the value every earlier run played with,
so that the runs made before keep their identity (and their folders resume)."""


class ProtocolSettings(TurnBudget):
    """A run's turn protocol: a preset, with any of its settings overridden."""

    preset: PresetName = Field(
        default=DEFAULT_PRESET,
        description="pare (PARE's protocol) or paper (the paper's, as far as it specifies it); the other "
        "fields given override the preset's values.",
    )
    max_format_retries: int = Field(
        default=FORMAT_RETRIES,
        ge=0,
        le=20,
        description="Times a malformed model answer is sent back within one step.",
    )

    @model_validator(mode="before")
    @classmethod
    def _apply_preset(cls, data: Any) -> Any:
        """The preset's values under the fields given (which override them)."""
        if not isinstance(data, dict):
            return data
        name = data.get("preset", DEFAULT_PRESET)
        if not isinstance(name, str):
            return data  # the field's own validation says what is wrong
        if name not in PRESETS:
            raise ValueError(
                f"unknown protocol preset '{name}' (the presets are {', '.join(PRESETS)})."
                f"{did_you_mean(name, PRESETS)}"
            )
        return {**PRESETS[name], **data}

    @field_validator("turn_duration", "reaction_horizon", mode="before")
    @classmethod
    def _duration(cls, value: Any) -> Any:
        if isinstance(value, str) and not value.startswith("P"):  # '1m', '90s'; ISO 8601 goes to pydantic
            try:
                return parse_duration(value)
            except TimeFormatError as error:
                raise ValueError(str(error)) from None
        return value

    def overrides(self) -> dict[str, Any]:
        """The settings that differ from the preset's, as JSON values (empty: the preset as it is)."""
        preset = ProtocolSettings(preset=self.preset).model_dump(mode="json")
        mine = self.model_dump(mode="json")
        return {name: value for name, value in mine.items() if value != preset[name]}

    def record(self) -> dict[str, Any]:
        """What a run's manifest records of its protocol: the preset, its overrides, every setting."""
        settings = self.model_dump(mode="json")
        return {"preset": self.preset, "overrides": self.overrides(), "settings": settings}

    def identity(self) -> dict[str, Any]:
        """The protocol's part of a run's identity (:data:`LEGACY_IDENTITY_FIELDS`)."""
        pare = ProtocolSettings().model_dump(mode="json")
        return {
            name: value
            for name, value in self.model_dump(mode="json").items()
            if name in LEGACY_IDENTITY_FIELDS or value != pare[name]
        }


def preset_differences(first: str, second: str) -> dict[str, tuple[Any, Any]]:
    """The settings in which two presets differ, each with its value in ``first`` and in ``second``."""
    one = ProtocolSettings.model_validate({"preset": first}).model_dump(mode="json")
    other = ProtocolSettings.model_validate({"preset": second}).model_dump(mode="json")
    return {name: (one[name], other[name]) for name in one if name != "preset" and one[name] != other[name]}


def manifest_protocol(manifest: Mapping[str, Any]) -> tuple[str, dict[str, Any]]:
    """The preset a run played and its overrides, from its manifest. A manifest written before presets
    has no ``protocol`` record: its run played PARE's protocol, with the settings its configuration
    changed as overrides.
    """
    record = manifest.get("protocol")
    if isinstance(record, Mapping) and isinstance(record.get("preset"), str):
        overrides = record.get("overrides")
        return record["preset"], dict(overrides) if isinstance(overrides, Mapping) else {}
    config = manifest.get("config")
    settings = config.get("protocol") if isinstance(config, Mapping) else None
    if not isinstance(settings, Mapping):
        return DEFAULT_PRESET, {}
    try:
        return DEFAULT_PRESET, ProtocolSettings.model_validate(dict(settings)).overrides()
    except ValidationError:  # a setting this version no longer reads: the preset is still known
        return DEFAULT_PRESET, {}
