"""What a benchmark run is: scenarios, runs, models per role, the turn protocol, the world, the machinery.

A run configuration comes from a YAML file (``pare run --config run.yaml``), from command-line flags, or
both: flags override the file, and ``--set path=value`` overrides any field by its dotted path. Nothing
secret lives here: a role's API key is read from the environment variable its model configuration names.

The *identity* of a configuration is what shapes an episode's behaviour (models and their sampling, the
turn protocol, the world's settings, the seed). It names the default output directory and is checked
when a run resumes, so episodes of two different configurations never mix in one store. Which
scenarios, how many runs, the concurrency and the cache mode are not part of it: a run can be extended
with more scenarios or runs and resumed with other machinery.
"""

from __future__ import annotations

import copy
import hashlib
import json
import re
from collections.abc import Sequence
from pathlib import Path
from typing import Any, Literal, cast

from pydantic import (
    BaseModel,
    ConfigDict,
    Field,
    ModelWrapValidatorHandler,
    PrivateAttr,
    ValidationError,
    ValidationInfo,
    field_validator,
    model_validator,
)

from pare.agents.models.cache import CacheMode
from pare.agents.models.config import ModelConfig
from pare.bench import policies as registry
from pare.bench.episode import EpisodeSettings
from pare.env import WorldSettings as WorldSettings  # re-exported: a run's world
from pare.errors import UserInputError
from pare.protocols import ProtocolSettings as ProtocolSettings  # re-exported: a run's protocol
from pare.results.run_folder import MAX_RUNS as MAX_RUNS  # re-exported: a run file's limit
from pare.yaml_source import UnreadableFile, YamlSyntaxError, load_yaml, read_text_file

ExecutionBackend = Literal["local", "ray"]

IDENTITY_MODEL_FIELDS = ("model", "backend", "temperature", "max_tokens", "seed", "extra")
"""The fields of a model configuration that can change what the model answers (timeouts, retries,
concurrency and prices cannot). The endpoint is left out, as in the model-call cache's key: a local
server that comes back on another port still serves the same run (the manifest records the endpoint)."""


MAX_CONCURRENCY = 4_096
"""The most episodes in flight at once."""


class ScenarioSelection(BaseModel):
    """Which scenarios to run: from the library (or ``paths``), narrowed by every filter given."""

    model_config = ConfigDict(extra="forbid", frozen=True, allow_inf_nan=False)

    ids: list[str] = Field(default_factory=list, description="Scenario ids; empty means all.")
    split: str | None = Field(default=None, description="A split from the library's splits.yaml.")
    apps: list[str] = Field(default_factory=list, description="Keep scenarios using any of these apps.")
    tags: list[str] = Field(default_factory=list, description="Keep scenarios with any of these tags.")
    difficulty: list[str] = Field(default_factory=list, description="Keep these difficulties.")
    kinds: list[Literal["proposal", "no_proposal"]] = Field(
        default_factory=list,
        description="Keep these kinds: 'proposal' (the right move is to propose) or 'no_proposal'.",
    )
    paths: list[str] = Field(
        default_factory=list, description="Scenario files or folders to use instead of the library."
    )


class Models(BaseModel):
    """The model behind each role. A role without a model is played by the scenario's oracle, unless
    ``policies`` names another player.

    ``assistant`` is a shorthand for the paper's symmetric setup: the same model observes and executes.
    """

    model_config = ConfigDict(extra="forbid", frozen=True, allow_inf_nan=False)

    user: ModelConfig | None = Field(default=None, description="The user simulator; none: oracle user.")
    assistant: ModelConfig | None = Field(
        default=None, description="Observe and execute both, unless they are given."
    )
    observe: ModelConfig | None = Field(default=None, description="The assistant in observe mode.")
    execute: ModelConfig | None = Field(default=None, description="The assistant in execute mode.")
    judge: ModelConfig | None = Field(
        default=None,
        description="Judges free-text checks; none: the user's model when there is one (as the paper's "
        "user simulator judges), else the checks' deterministic fallback.",
    )
    deterministic_judge: bool = Field(
        default=False,
        description="Judge free-text checks by their deterministic fallback even when models are set.",
    )

    _inherited: dict[str, str] = PrivateAttr(default_factory=dict)
    """Roles that were not set and took another role's model: role -> the role it came from."""

    @model_validator(mode="wrap")
    @classmethod
    def _fill_roles(cls, data: Any, handler: ModelWrapValidatorHandler[Models]) -> Models:
        if not isinstance(data, dict):
            return handler(data)
        data = dict(data)
        inherited: dict[str, str] = {}
        for mode in ("observe", "execute"):
            if data.get(mode) is None and data.get("assistant") is not None:
                data[mode] = data["assistant"]
                inherited[mode] = "assistant"
        if data.get("execute") is None and data.get("observe") is not None:
            data["execute"] = data["observe"]  # one observe model does both, as with 'assistant'
            inherited["execute"] = "observe"
        if data.get("observe") is None and data.get("execute") is not None:
            raise ValueError("an execute model needs an observe model (or set 'assistant' for both)")
        if data.get("deterministic_judge"):
            if data.get("judge") is not None:
                raise ValueError("give a judge model or deterministic_judge, not both")
        elif data.get("judge") is None and data.get("user") is not None:
            # free text is judged by a model whenever models play: the paper's user simulator judges
            data["judge"] = data["user"]
            inherited["judge"] = "user"
        models = handler(data)
        models._inherited = inherited
        return models

    def inherited_from(self, role: str) -> str | None:
        """The role whose model ``role`` took because it was not set itself (``None``: set, or unset)."""
        return self._inherited.get(role)

    def roles(self) -> dict[str, ModelConfig]:
        """The configured roles, by name (``assistant`` folded into observe and execute)."""
        configured = {
            "user": self.user,
            "observe": self.observe,
            "execute": self.execute,
            "judge": self.judge,
        }
        return {role: config for role, config in configured.items() if config is not None}


class Policies(BaseModel):
    """Who plays each role (see :mod:`pare.bench.policies`): a built-in name (``model``, ``oracle``, ...)
    or your own as ``MODULE:FACTORY``. Unset: the role's model when it has one, else the oracle (for the
    judge, the checks' deterministic fallbacks).
    """

    model_config = ConfigDict(extra="forbid", frozen=True)

    user: str | None = Field(
        default=None, description="The user: model, oracle, slow, busy, silent, human (pare play), or M:F."
    )
    assistant: str | None = Field(
        default=None, description="The assistant: model, oracle, a baseline (silent, ...), or MODULE:FACTORY."
    )
    judge: str | None = Field(
        default=None, description="The judge of free-text checks: model, deterministic, or MODULE:FACTORY."
    )

    @field_validator("user", "assistant", "judge")
    @classmethod
    def _known(cls, value: str | None, info: ValidationInfo) -> str | None:
        if value is not None:
            registry.check_name(cast(registry.PolicyRole, info.field_name), value)
        return value


class RunConfig(BaseModel):
    """Everything one benchmark run needs."""

    model_config = ConfigDict(extra="forbid", frozen=True, allow_inf_nan=False)

    name: str | None = Field(default=None, description="A label for reports and the output folder.")
    scenarios: ScenarioSelection = Field(default_factory=ScenarioSelection)
    runs: int = Field(default=4, ge=1, le=MAX_RUNS, description="Runs per scenario (k of Success@k).")
    seed: int = Field(
        default=0, ge=0, lt=2**63, description="Base seed; each episode's seed derives from it."
    )
    models: Models = Field(default_factory=Models)
    policies: Policies = Field(default_factory=Policies)
    protocol: ProtocolSettings = Field(default_factory=ProtocolSettings)
    world: WorldSettings = Field(default_factory=WorldSettings)
    concurrency: int = Field(default=8, ge=1, le=MAX_CONCURRENCY, description="Episodes in flight at once.")
    episode_retries: int = Field(
        default=2, ge=0, le=100, description="Reruns of an episode that failed for infrastructure reasons."
    )
    cache: CacheMode = Field(default="read_write", description="Model-call cache: off, read_write, replay.")
    cache_path: str | None = Field(
        default=None, description="The cache file; default: model_calls.sqlite in the output folder."
    )
    output: str | None = Field(default=None, description="Run folder; default: runs/<label>-<identity>.")
    backend: ExecutionBackend = Field(default="local", description="local (asyncio) or ray.")
    ray_address: str | None = Field(default=None, description="Ray cluster address; none: local Ray.")

    @model_validator(mode="before")
    @classmethod
    def _judge_without_model(cls, data: Any) -> Any:
        # A judge named 'deterministic' does not take the user's model as a judge would by default.
        if not isinstance(data, dict):
            return data
        named = data.get("policies")
        models = data.get("models")
        if not (isinstance(named, dict) and named.get("judge") == registry.DETERMINISTIC):
            return data
        if models is None or (isinstance(models, dict) and models.get("judge") is None):
            return {**data, "models": {**(models or {}), "deterministic_judge": True}}
        return data

    @model_validator(mode="after")
    def _policies_fit_models(self) -> RunConfig:
        for role in registry.POLICY_ROLES:
            name = getattr(self.policies, role)
            built_in = registry.BUILT_IN[role].get(name) if name is not None else None
            if built_in is None:
                continue  # unset (the default fits), or your own: it takes the role's models if it has any
            models = ", ".join(f"models.{model}" for model in self._role_models(role))
            if built_in.uses_model and not self._role_models(role):
                raise ValueError(
                    f"policies.{role} is '{name}', but no {role} model is configured: give one "
                    f"(--{role}-model, or models.{role} in the run file), or another policy"
                )
            if not built_in.uses_model and self._role_models(role):
                raise ValueError(
                    f"policies.{role} is '{name}', which plays without a model, but {models} is set: "
                    "leave out the model or the policy"
                )
        return self

    # -- derived -----------------------------------------------------------------------------------------
    @property
    def oracle_only(self) -> bool:
        """Whether no role has a model (the offline pipeline run)."""
        return not self.models.roles()

    def _role_models(self, role: registry.PolicyRole) -> dict[str, ModelConfig]:
        """The configured models a policy of ``role`` is given, by name (see ``registry.MODEL_ROLES``)."""
        configured = self.models.roles()
        return {name: configured[name] for name in registry.MODEL_ROLES[role] if name in configured}

    def policy(self, role: registry.PolicyRole) -> str:
        """The name of the policy that plays ``role``: the one named, else the role's default."""
        named: str | None = getattr(self.policies, role)
        return named or registry.default_policy(role, bool(self._role_models(role)))

    def policy_names(self) -> dict[str, str]:
        """Every role's policy name (the manifest records them)."""
        return {role: self.policy(role) for role in registry.POLICY_ROLES}

    def custom_policies(self) -> dict[str, str]:
        """The roles whose policy is not the default for their models (a part of the identity)."""
        return {
            role: self.policy(role)
            for role in registry.POLICY_ROLES
            if self.policy(role) != registry.default_policy(role, bool(self._role_models(role)))
        }

    def episode_settings(self, seed: int) -> EpisodeSettings:
        """The episode loop's settings for one episode with environment seed ``seed``."""
        budget = self.protocol.budget().model_dump()
        return EpisodeSettings.model_validate({**budget, "env": self.world.env_config(seed)})

    def identity(self) -> dict[str, Any]:
        """What shapes an episode's behaviour, as JSON (no secret: keys are never in a configuration). The
        policies appear only when one is not the default (a run made before they could be named resumes).
        """
        identity: dict[str, Any] = {
            "seed": self.seed,
            "models": {
                role: {
                    name: value
                    for name, value in config.public_dict().items()
                    if name in IDENTITY_MODEL_FIELDS
                }
                | {"native_tools": config.native_tools}
                for role, config in self.models.roles().items()
            },
            "protocol": self.protocol.identity(),
            "world": self.world.model_dump(mode="json"),
        }
        custom = self.custom_policies()
        if custom:
            identity["policies"] = custom
        return identity

    def identity_hash(self) -> str:
        """A short hash of :meth:`identity`."""
        return hashlib.sha256(_canonical(self.identity()).encode("utf-8")).hexdigest()[:10]

    def label(self) -> str:
        """The configuration's name: ``name``, else who plays the assistant and the user (a model, the
        oracle, or a named policy with its models in brackets).
        """
        if self.name:
            return self.name
        roles = self.models.roles()
        observe, execute, user = roles.get("observe"), roles.get("execute"), roles.get("user")
        models = ""
        if observe is not None:
            models = observe.model
            if execute is not None and execute.model != observe.model:
                models = f"{observe.model}+{execute.model}"
        assistant = self._player("assistant", models)
        user_models = user.model if user is not None else ""
        if user is None and "user" not in self.custom_policies():
            return assistant
        return f"{assistant} (user {self._player('user', user_models)})"

    def _player(self, role: registry.PolicyRole, models: str) -> str:
        """How the label names who plays ``role``: its model, the oracle, or the policy (with its models)."""
        name = self.policy(role)
        if name == registry.MODEL:
            return models
        return f"{name}[{models}]" if models else name

    def judge_provenance(self) -> dict[str, Any]:
        """Who judges the scenarios' free-text checks: a model (and whether it was set or taken from the
        user's role), or the checks' deterministic fallbacks. For the manifest and what ``pare run`` prints.
        """
        judge = self.models.judge
        policy = self.policy("judge")
        custom = {"policy": policy} if registry.is_import_path(policy) else {}
        if judge is None:
            return {"model": None, "inherited_from": None, "deterministic_fallback": not custom} | custom
        return custom | {
            "model": judge.model,
            "backend": judge.backend,
            "endpoint": judge.endpoint(),
            "inherited_from": self.models.inherited_from("judge"),
            "deterministic_fallback": False,
        }

    def output_dir(self) -> Path:
        """The run folder: ``output`` when given, else ``runs/<slug of label>-<identity hash>``."""
        if self.output:
            return Path(self.output)
        return Path("runs") / f"{slug(self.label())}-{self.identity_hash()}"

    def public_dict(self) -> dict[str, Any]:
        """The resolved configuration for the manifest: every field, endpoints without credentials."""
        data = self.model_dump(mode="json")
        data["models"] = {role: config.public_dict() for role, config in self.models.roles().items()}
        return data

    def episode_seed(self, scenario_id: str, run: int) -> int:
        """The environment seed of one episode: stable, different per scenario and run."""
        digest = hashlib.sha256(f"{self.seed}:{scenario_id}:{run}".encode()).digest()
        return int.from_bytes(digest[:4], "big")


def slug(text: str) -> str:
    """A folder-safe form of ``text``."""
    cleaned = re.sub(r"[^A-Za-z0-9._+-]+", "-", text).strip("-.")
    return cleaned[:80] or "run"


def _canonical(value: Any) -> str:
    return json.dumps(value, sort_keys=True, separators=(",", ":"), ensure_ascii=False)


# -- building a configuration from a file and overrides ---------------------------------------------------
def read_config_file(path: str | Path) -> dict[str, Any]:
    """The mapping in a YAML configuration file, with a clear error when it cannot be read."""
    file = Path(path)
    try:
        data = load_yaml(read_text_file(file))
    except FileNotFoundError:
        raise UserInputError(f"cannot read the configuration file {file}: no such file") from None
    except UnreadableFile as error:
        raise UserInputError(f"cannot read the configuration file {file}: {error}") from None
    except YamlSyntaxError as error:
        where = f"{file}:{error.line}" if error.line is not None else str(file)
        raise UserInputError(f"{where}: {error}") from None
    if data is None:
        return {}
    if not isinstance(data, dict):
        raise UserInputError(
            f"{file}: a run configuration is a mapping of settings, not {type(data).__name__}"
        )
    return data


def set_path(data: dict[str, Any], dotted: str, value: Any) -> None:
    """Set ``data[a][b][c] = value`` for ``dotted`` ``a.b.c``, creating mappings on the way."""
    parts = dotted.split(".")
    if not all(parts):
        raise UserInputError(f"'{dotted}' is not a dotted setting path like 'protocol.max_turns'")
    node = data
    for part in parts[:-1]:
        child = node.get(part)
        if child is None:
            child = node[part] = {}
        elif not isinstance(child, dict):
            raise UserInputError(f"cannot set '{dotted}': '{part}' is a value, not a group of settings")
        node = child
    node[parts[-1]] = value


def parse_assignment(text: str) -> tuple[str, Any]:
    """``path=value`` from ``--set``; the value is read as YAML (numbers, lists, null, mappings)."""
    path, sep, raw = text.partition("=")
    if not sep or not path.strip():
        raise UserInputError(f"--set expects path=value (e.g. protocol.max_turns=20), got '{text}'")
    try:
        value = load_yaml(raw) if raw.strip() else ""
    except YamlSyntaxError as error:
        raise UserInputError(f"--set {text}: the value cannot be read: {error}") from None
    return path.strip(), value


def build_config(
    data: dict[str, Any] | None = None,
    *,
    overrides: Sequence[tuple[str, Any]] = (),
    source: str = "configuration",
) -> RunConfig:
    """Validate ``data`` with ``overrides`` applied (dotted paths), listing every problem with its path."""
    merged: dict[str, Any] = copy.deepcopy(data or {})
    for path, value in overrides:
        set_path(merged, path, value)
    try:
        return RunConfig.model_validate(merged)
    except ValidationError as error:
        problems = [
            f"  {'.'.join(str(p) for p in problem['loc']) or '(top level)'}: {problem['msg']}"
            for problem in error.errors()
        ]
        raise UserInputError(f"{source} is not a valid run configuration:\n" + "\n".join(problems)) from None
