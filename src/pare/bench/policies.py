"""Who plays each role of an episode: a policy named in the run configuration, built in or your own.

A run names the policy of the user, the assistant and the judge by a string (``policies.assistant`` in a
run file, ``--assistant-policy`` on the command line). A name is recorded in the manifest, compared when
a run resumes, and sent as it is to Ray workers, which resolve it themselves: objects cannot travel
between processes, names can. A name is either

* built in (:data:`BUILT_IN`): ``model`` (PARE's model-backed actor on the role's configured model),
  ``oracle`` (the scenario's solution), and the scripted players of the scenario self-test (``silent``,
  ``unrelated``, ``slow``, ``busy``), useful as baselines, and ``human``, a person in the user's
  seat, who plays only through ``pare play``; or
* an import path ``MODULE:FACTORY`` (``my_agents:make_assistant``, ``my_pkg.agents:Scaffold.build``).
  ``MODULE`` is imported as Python imports it (installed, on ``PYTHONPATH``, or in the current folder);
  ``FACTORY`` is an attribute of it, dotted for nested ones.

A factory is called once per episode with one argument, a :class:`PolicyContext`, and returns a new
policy: an :class:`~pare.agents.policy.AssistantPolicy` for the assistant, a
:class:`~pare.agents.policy.UserPolicy` for the user, a :class:`~pare.scenarios.checks.Judge` (an async
callable: ``await judge(criterion, text, facts)`` gives a ``JudgeVerdict``) for the judge. A class whose
constructor takes the context is a factory too.
"""

from __future__ import annotations

import importlib
import os
import re
import sys
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Literal, get_args

from pare.agents.policy import AssistantPolicy, UserPolicy
from pare.errors import UserInputError, did_you_mean

if TYPE_CHECKING:
    from pare.agents.llm import ChatModel
    from pare.agents.models.config import ModelConfig
    from pare.scenarios.model import Scenario

PolicyRole = Literal["user", "assistant", "judge"]
POLICY_ROLES: tuple[PolicyRole, ...] = get_args(PolicyRole)

MODEL_ROLES: dict[PolicyRole, tuple[str, ...]] = {
    "user": ("user",),
    "assistant": ("observe", "execute"),
    "judge": ("judge",),
}
"""The configured models (``models.<name>``) a policy of each role is given, the first being its main one."""

_IMPORT_PATH = re.compile(r"^[A-Za-z_]\w*(\.[A-Za-z_]\w*)*:[A-Za-z_]\w*(\.[A-Za-z_]\w*)*$")


@dataclass(frozen=True)
class PolicyContext:
    """What a policy factory is given for one episode.

    ``models`` holds the role's configured models by name (``user``; ``observe`` and ``execute`` for the
    assistant; ``judge``), each the run's shared client bound to this episode: its calls go through the
    record/replay cache and the endpoint's concurrency and rate limits, and count in the reports' tokens
    and cost. A role without a configured model gets none.
    """

    role: PolicyRole
    scenario: Scenario
    """The scenario being played. The oracle reads its solution; an assistant under evaluation should act
    on what it observes, not on this."""
    run: int
    """The run index, 1 to k."""
    seed: int
    """The episode's environment seed (stable for the scenario and run): seed your own randomness with it."""
    models: Mapping[str, ChatModel] = field(default_factory=dict)
    model_configs: Mapping[str, ModelConfig] = field(default_factory=dict)
    """The configurations behind ``models`` (model name, sampling, ``native_tools``, ...), without keys."""
    max_format_retries: int = 2
    """Times a malformed model answer is sent back within one step (``protocol.max_format_retries``)."""

    def model(self, name: str | None = None) -> ChatModel:
        """The configured model ``name`` (default: the role's main one: ``user``, ``observe`` or ``judge``).

        Raises:
            UserInputError: No such model is configured for this role.
        """
        wanted = name or MODEL_ROLES[self.role][0]
        found = self.models.get(wanted)
        if found is None:
            raise UserInputError(
                f"the {self.role} policy needs the '{wanted}' model, but none is configured: "
                f"give --{_model_flag(wanted)}-model (or models.{_model_flag(wanted)} in the run file)"
            )
        return found


def _model_flag(model_role: str) -> str:
    return "assistant" if model_role == "observe" else model_role


Factory = Callable[[PolicyContext], Any]


# -- the built-in policies --------------------------------------------------------------------------------
def _model_user(context: PolicyContext) -> Any:
    from pare.agents.llm import LLMUser

    return LLMUser(
        context.model("user"),
        persona=context.scenario.user.persona,
        goal=context.scenario.user.goal,
        native_tools=context.model_configs["user"].native_tools,
        max_format_retries=context.max_format_retries,
    )


def _model_assistant(context: PolicyContext) -> Any:
    from pare.agents.llm import LLMAssistant

    return LLMAssistant(
        context.model("observe"),
        context.model("execute"),
        native_tools=context.model_configs["observe"].native_tools,
        max_format_retries=context.max_format_retries,
    )


def _model_judge(context: PolicyContext) -> Any:
    from pare.agents.judge import ModelJudge

    return ModelJudge(context.model("judge"), context.model_configs["judge"].model)


def _oracle_user(context: PolicyContext) -> Any:
    from pare.scenarios.oracle import OracleUser

    return OracleUser(context.scenario)


def _accept_all_user(context: PolicyContext) -> Any:
    from pare.scenarios.oracle import AcceptAllUser

    return AcceptAllUser(context.scenario)


def _strict_oracle_user(context: PolicyContext) -> Any:
    from pare.scenarios.oracle import StrictOracleUser

    return StrictOracleUser(context.scenario)


def _slow_user(context: PolicyContext) -> Any:
    from pare.scenarios.oracle import SlowUser

    return SlowUser(context.scenario)


def _busy_user(context: PolicyContext) -> Any:
    from pare.scenarios.oracle import BusyUser

    return BusyUser(context.scenario)


def _silent_user(context: PolicyContext) -> Any:
    from pare.agents.policy import SilentUser

    return SilentUser()


def _human_user(context: PolicyContext) -> Any:
    raise UserInputError(
        f"the '{HUMAN}' user is a person: it plays through 'pare play SCENARIO', which asks them each action"
    )


def _oracle_assistant(context: PolicyContext) -> Any:
    from pare.scenarios.oracle import OracleAssistant

    return OracleAssistant(context.scenario)


def _silent_assistant(context: PolicyContext) -> Any:
    from pare.agents.policy import SilentAssistant

    return SilentAssistant()


def _unrelated_assistant(context: PolicyContext) -> Any:
    from pare.scenarios.oracle import UnrelatedAssistant

    return UnrelatedAssistant(context.scenario)


def _baseline(name: str) -> Factory:
    def build(context: PolicyContext) -> Any:
        from pare.scenarios.baselines import BASELINES

        return BASELINES[name].build(context.scenario, context.seed)

    return build


def _deterministic_judge(context: PolicyContext) -> Any:
    return None  # no judge: each free-text check is read by its deterministic fallback


@dataclass(frozen=True)
class BuiltIn:
    """A policy PARE ships, under its name."""

    factory: Factory
    description: str
    uses_model: bool = False
    """It plays the role's configured model (and needs one); the others play without a model."""


MODEL = "model"
ORACLE = "oracle"
HUMAN = "human"
"""A person in the user's seat (``pare play``); a run of many episodes cannot ask one."""
DETERMINISTIC = "deterministic"

BUILT_IN: dict[PolicyRole, dict[str, BuiltIn]] = {
    "user": {
        MODEL: BuiltIn(_model_user, "the user simulator on the user's model", uses_model=True),
        ORACLE: BuiltIn(_oracle_user, "the scenario's scripted user steps; accepts every proposal"),
        "oracle_strict": BuiltIn(
            _strict_oracle_user,
            "the oracle user who accepts only the scenario's right proposals, word for word",
        ),
        "accept_all": BuiltIn(
            _accept_all_user, "the oracle user by another name: accepts everything at once"
        ),
        "slow": BuiltIn(_slow_user, "the oracle user with a harmless extra step before each of its own"),
        "busy": BuiltIn(_busy_user, "the oracle user who never waits (a harmless step instead)"),
        "silent": BuiltIn(_silent_user, "a user who only waits (never answers a proposal)"),
        HUMAN: BuiltIn(_human_user, "a person, at the terminal or in the browser (pare play only)"),
    },
    "assistant": {
        MODEL: BuiltIn(
            _model_assistant, "PARE's assistant on the observe and execute models", uses_model=True
        ),
        ORACLE: BuiltIn(_oracle_assistant, "the scenario's solution: proposes and does the right task"),
        "silent": BuiltIn(_silent_assistant, "an assistant that only waits (the do-nothing baseline)"),
        "unrelated": BuiltIn(
            _unrelated_assistant, "proposes and does a plausible task unrelated to the scenario"
        ),
        "generic_offer": BuiltIn(
            _baseline("generic_offer"), "offers vague help whenever nothing is pending; does nothing"
        ),
        "propose_only": BuiltIn(
            _baseline("propose_only"), "proposes the right task at the right time, then does none of it"
        ),
        "random": BuiltIn(_baseline("random"), "reads, waits and offers help at random; random calls"),
    },
    "judge": {
        MODEL: BuiltIn(_model_judge, "the judge model reads free-text checks", uses_model=True),
        DETERMINISTIC: BuiltIn(_deterministic_judge, "each free-text check's deterministic fallback"),
    },
}


def default_policy(role: PolicyRole, has_model: bool) -> str:
    """The policy a role gets when none is named: its model when it has one, else the oracle (the judge:
    the checks' deterministic fallbacks).
    """
    if has_model:
        return MODEL
    return DETERMINISTIC if role == "judge" else ORACLE


def is_import_path(name: str) -> bool:
    """Whether ``name`` is written as ``MODULE:FACTORY`` rather than a built-in name."""
    return ":" in name


def check_name(role: PolicyRole, name: str) -> None:
    """Check how ``name`` is written (no import): a built-in name of ``role`` or ``MODULE:FACTORY``.

    Raises:
        ValueError: Neither; the message suggests the closest built-in name.
    """
    if name in BUILT_IN[role]:
        return
    if is_import_path(name):
        if not _IMPORT_PATH.match(name):
            raise ValueError(
                f"'{name}' is not an import path MODULE:FACTORY (dotted Python names on both sides of one "
                "colon, e.g. my_agents:make_assistant)"
            )
        return
    choices = sorted(BUILT_IN[role])
    raise ValueError(
        f"unknown {role} policy '{name}'.{did_you_mean(name, choices)} Built in: {', '.join(choices)}; "
        "or your own as MODULE:FACTORY"
    )


def resolve(role: PolicyRole, name: str) -> Factory:
    """The factory ``name`` stands for: a built-in one, or the attribute an import path names.

    Raises:
        UserInputError: The name is unknown, its module cannot be imported, it has no such attribute, or
            the attribute cannot be called.
    """
    try:
        check_name(role, name)
    except ValueError as error:
        raise UserInputError(str(error)) from None
    built_in = BUILT_IN[role].get(name)
    if built_in is not None:
        return built_in.factory
    module_name, _, attribute_path = name.partition(":")
    target: Any = _import(role, name, module_name)
    walked = module_name
    for part in attribute_path.split("."):
        if not hasattr(target, part):
            public = [attr for attr in dir(target) if not attr.startswith("_")]
            raise UserInputError(
                f"{role} policy '{name}': '{walked}' has no attribute '{part}'.{did_you_mean(part, public)}"
            )
        target = getattr(target, part)
        walked = f"{walked}{':' if walked == module_name else '.'}{part}"
    if not callable(target):
        raise UserInputError(
            f"{role} policy '{name}' is a {type(target).__name__}, not a factory: name a function or class "
            "that takes a PolicyContext and returns the policy"
        )
    factory: Factory = target
    return factory


def _import(role: PolicyRole, name: str, module_name: str) -> Any:
    """Import ``module_name``. A module not found is looked for in the current folder too, as
    ``python -m`` would: ``pare`` started as a command does not have that folder on its path, and a module
    written beside the run file is what people mean.
    """
    while True:
        try:
            return importlib.import_module(module_name)
        except ModuleNotFoundError as error:
            missing = error.name or module_name
            itself = module_name == missing or module_name.startswith(missing + ".")
            here = os.getcwd()
            if itself and here not in sys.path:
                sys.path.append(here)
                continue
            if itself:
                raise UserInputError(
                    f"{role} policy '{name}': no module named '{missing}' (searched the installed packages, "
                    "PYTHONPATH and the current folder)"
                ) from None
            raise UserInputError(
                f"{role} policy '{name}': importing '{module_name}' failed: it imports '{missing}', which "
                "is not installed"
            ) from None
        except Exception as error:  # the module itself is broken: say so in its own words
            raise UserInputError(
                f"{role} policy '{name}': importing '{module_name}' failed: {type(error).__name__}: {error}"
            ) from None


@dataclass(frozen=True)
class Player:
    """A role's policy, resolved once for a run: its name and factory."""

    role: PolicyRole
    name: str
    factory: Factory

    @classmethod
    def resolve(cls, role: PolicyRole, name: str) -> Player:
        """The policy ``name`` plays ``role`` with (see :func:`resolve`)."""
        return cls(role, name, resolve(role, name))

    def build(self, context: PolicyContext) -> Any:
        """A new policy for one episode: the factory called with ``context``, checked to be what the role
        needs (``None`` is allowed for the built-in judges only: the deterministic fallbacks).

        Raises:
            UserInputError: The factory returned something that cannot play the role.
        """
        policy = self.factory(context)
        _check_built(self.role, self.name, policy)
        return policy


def build(role: PolicyRole, name: str, context: PolicyContext) -> Any:
    """A new policy for one episode, ``name`` resolved and built (see :meth:`Player.build`).

    Raises:
        UserInputError: The name cannot be resolved (see :func:`resolve`), or the factory returned
            something that cannot play the role.
    """
    return Player.resolve(role, name).build(context)


def _check_built(role: PolicyRole, name: str, policy: Any) -> None:
    wanted: dict[PolicyRole, tuple[type, str]] = {
        "user": (UserPolicy, "a pare.agents.UserPolicy (subclass it and implement step)"),
        "assistant": (
            AssistantPolicy,
            "a pare.agents.AssistantPolicy (subclass it and implement observe and execute)",
        ),
    }
    if role == "judge":
        if policy is None and name in BUILT_IN["judge"]:
            return
        if callable(policy):
            return
        what = "a judge: an async callable, await judge(criterion, text, facts) -> JudgeVerdict"
    else:
        kind, what = wanted[role]
        if isinstance(policy, kind):
            return
    raise UserInputError(f"{role} policy '{name}' returned {_described(policy)}, not {what}")


def _described(value: Any) -> str:
    if value is None:
        return "None"
    return f"a {type(value).__module__}.{type(value).__qualname__}"


def describe(role: PolicyRole) -> Mapping[str, str]:
    """The built-in policies of ``role`` with what each does (for help texts and documentation)."""
    return {name: entry.description for name, entry in BUILT_IN[role].items()}
