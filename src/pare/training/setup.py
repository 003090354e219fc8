"""What a training environment plays: the scenarios it samples from, the turn protocol, the other role.

Shared by the Gymnasium environments and the verifiers environment, so both choose scenarios, seed the
world and build the counterpart the same way.
"""

from __future__ import annotations

import random
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any, Literal

from pydantic import ValidationError

from pare.agents.llm import ChatModel, LLMAssistant, LLMUser
from pare.agents.models.client import ModelClient
from pare.agents.models.config import ModelConfig
from pare.agents.policy import AssistantPolicy, UserPolicy
from pare.bench.episode import EpisodeSettings
from pare.env import EnvConfig
from pare.errors import UserInputError, did_you_mean
from pare.protocols import ProtocolSettings
from pare.scenarios.library import get_scenario, splits
from pare.scenarios.model import Scenario
from pare.scenarios.oracle import OracleAssistant, OracleUser

ORACLE: Literal["oracle"] = "oracle"
"""The counterpart that plays the scenario's solution."""

Counterpart = Literal["oracle"] | ChatModel | ModelConfig | Mapping[str, Any]
"""Who plays the other role: the oracle, a model (anything with PARE's ``complete``), or a model
configuration (a :class:`~pare.agents.models.config.ModelConfig` or its fields as a mapping)."""

DEFAULT_SPLIT = "smoke"
"""The split an environment samples from when given neither scenarios nor a split."""


def scenario_pool(scenarios: Sequence[str] | None = None, split: str | None = None) -> tuple[str, ...]:
    """The scenario ids to sample from: ``scenarios`` when given, else the split's (default: ``smoke``),
    sorted so that a seed picks the same scenario whatever order they were given in.

    Raises:
        UserInputError: both or an unknown split or scenario id given, or the selection is empty.
    """
    if scenarios is not None and split is not None:
        raise UserInputError("give scenarios or a split, not both")
    if scenarios is not None:
        ids = tuple(sorted(scenarios))
        for scenario_id in ids:
            get_scenario(scenario_id)  # an unknown id fails here, with "did you mean"
    else:
        name = split or DEFAULT_SPLIT
        available = splits()
        if name not in available:
            raise UserInputError(
                f"no split '{name}'.{did_you_mean(name, available)} Splits: {', '.join(available)}"
            )
        ids = tuple(sorted(available[name]))
    if not ids:
        raise UserInputError("the environment has no scenario to play: give at least one scenario id")
    return ids


def choose_scenario(pool: Sequence[str], options: Mapping[str, Any] | None, rng: random.Random) -> Scenario:
    """The scenario of one episode: ``options["scenario"]`` (an id) when given, else one drawn by ``rng``
    from ``options["split"]`` when given, else from ``pool``.

    Raises:
        UserInputError: an unknown option, scenario or split.
    """
    options = dict(options or {})
    unknown = sorted(set(options) - {"scenario", "split"})
    if unknown:
        raise UserInputError(f"reset options {unknown} are unknown; the options are 'scenario' and 'split'")
    if options.get("scenario") is not None:
        if options.get("split") is not None:
            raise UserInputError("reset options: give 'scenario' or 'split', not both")
        return get_scenario(str(options["scenario"]))
    if options.get("split") is not None:
        pool = scenario_pool(split=str(options["split"]))
    return get_scenario(pool[rng.randrange(len(pool))])


def protocol_settings(protocol: str | Mapping[str, Any] | ProtocolSettings | None) -> ProtocolSettings:
    """The turn protocol: a preset's name (``pare``, ``paper``), a preset with overrides as a mapping
    (``{"preset": "paper", "max_turns": 20}``), or settings already made; ``None`` is PARE's protocol.

    Raises:
        UserInputError: the protocol is not valid, saying why.
    """
    if isinstance(protocol, ProtocolSettings):
        return protocol
    data: Mapping[str, Any] = (
        {} if protocol is None else {"preset": protocol} if isinstance(protocol, str) else protocol
    )
    try:
        return ProtocolSettings.model_validate(dict(data))
    except ValidationError as error:
        raise UserInputError(f"protocol: {error}") from None


def episode_settings(protocol: ProtocolSettings, seed: int) -> EpisodeSettings:
    """The episode loop's settings: the protocol's turn budget, the world seeded with ``seed``."""
    return EpisodeSettings.model_validate({**protocol.budget().model_dump(), "env": EnvConfig(seed=seed)})


@dataclass
class Counterparts:
    """Builds the policy of the role the agent does not play, one per episode, and owns the model clients
    it opened for model configurations (closed by :meth:`aclose`).
    """

    who: Counterpart
    max_format_retries: int
    clients: list[ModelClient] = field(default_factory=list)
    _model: ChatModel | None = None

    def __post_init__(self) -> None:
        if isinstance(self.who, str) and self.who != ORACLE:
            raise UserInputError(
                f"the other role is played by '{ORACLE}', a model or a model configuration, not '{self.who}'"
            )

    def _chat_model(self, role: str) -> ChatModel:
        if self._model is None:
            who = self.who
            if isinstance(who, Mapping):
                try:
                    who = ModelConfig.model_validate(dict(who))
                except ValidationError as error:
                    raise UserInputError(f"the {role}'s model configuration: {error}") from None
            if isinstance(who, ModelConfig):
                client = ModelClient(who, role)
                self.clients.append(client)
                self._model = client
            else:
                self._model = who  # type: ignore[assignment]
        assert self._model is not None
        return self._model

    def user(self, scenario: Scenario) -> UserPolicy:
        """The simulated user for ``scenario``: the oracle, or PARE's user simulator on the model."""
        if isinstance(self.who, str):
            return OracleUser(scenario)
        return LLMUser(
            self._chat_model("user"),
            persona=scenario.user.persona,
            goal=scenario.user.goal,
            max_format_retries=self.max_format_retries,
        )

    def assistant(self, scenario: Scenario) -> AssistantPolicy:
        """The assistant for ``scenario``: the oracle, or PARE's assistant on the model."""
        if isinstance(self.who, str):
            return OracleAssistant(scenario)
        return LLMAssistant(self._chat_model("assistant"), max_format_retries=self.max_format_retries)

    async def aclose(self) -> None:
        """Close the model clients opened for model configurations."""
        for client in self.clients:
            await client.aclose()
        self.clients.clear()
        self._model = None
