"""The build layer of a run: what each episode is played by, made from the run's configuration.

A run's configuration names a model and a policy for each role; this module turns them into things that
play: one client per configured role, shared by every episode of the run (its cache, its endpoint's
concurrency and rate limits, its usage ledger), and, per episode, the user, the assistant and the judge
the role's policy builds from this episode's view of those clients (:meth:`RunModels.actors`). The batch
layer (:mod:`pare.bench.runner`) plans the episodes and schedules them; it asks this one for actors.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

from pare.agents.models.cache import ModelCallCache
from pare.agents.models.client import ModelClient
from pare.agents.models.config import ModelConfig
from pare.agents.models.ledger import UsageLedger
from pare.agents.models.limiter import EndpointLimiter, LimiterState
from pare.agents.models.request_params import RequestParams
from pare.agents.models.types import ChatMessage, Completion
from pare.agents.policy import AssistantPolicy, UserPolicy
from pare.bench.policies import HUMAN, MODEL_ROLES, POLICY_ROLES, Player, PolicyContext, PolicyRole
from pare.bench.run_requests import RunRequests
from pare.bench.runconfig import RunConfig
from pare.bench.store import CACHE_FILE
from pare.errors import UserInputError
from pare.scenarios.model import Scenario

if TYPE_CHECKING:  # imported where a run has models: an oracle run never loads the actors or the prompts
    from pare.agents.llm import ChatModel
    from pare.scenarios.checks import Judge


@dataclass(frozen=True)
class EpisodePlan:
    """One episode to play."""

    scenario: Scenario
    run: int
    seed: int
    scenario_hash: str

    @property
    def key(self) -> tuple[str, int]:
        """The episode's key in the store."""
        return (self.scenario.id, self.run)

    @property
    def namespace(self) -> str:
        """The model-call cache namespace: each run of a scenario samples its models on its own."""
        return f"{self.scenario.id}/run-{self.run}"


@dataclass
class EpisodeModel:
    """A role's model as one episode sees it: the run's shared client, this episode's cache namespace,
    and a ledger of this episode's own calls.
    """

    client: ModelClient
    namespace: str
    ledger: UsageLedger

    async def complete(
        self, messages: Sequence[ChatMessage], tools: Sequence[dict[str, Any]] | None = None
    ) -> Completion:
        """The model's answer (see :meth:`ModelClient.complete`)."""
        return await self.client.complete(messages, tools, namespace=self.namespace, ledger=self.ledger)


@dataclass
class JudgeModel:
    """A judge's model outside a run (the self-test gate asks it about reactive events' texts): each call
    gets a client of its own and closes it, so there is nothing to close afterwards. In a run the judge
    calls through the run's shared client instead (:meth:`RunModels.actors`), under its endpoint's limit.
    """

    config: ModelConfig
    cache: ModelCallCache | None
    namespace: str
    ledger: UsageLedger
    params: RequestParams | None = None
    """The run's request parameters for the judge (what one call learns, the next ones know)."""

    async def complete(
        self, messages: Sequence[ChatMessage], tools: Sequence[dict[str, Any]] | None = None
    ) -> Completion:
        """The judge's answer."""
        async with ModelClient(self.config, "judge", self.cache, params=self.params) as client:
            return await client.complete(messages, tools, namespace=self.namespace, ledger=self.ledger)


@dataclass
class RunModels:
    """The model clients of one run (one per configured role), shared by its episodes."""

    config: RunConfig
    cache: ModelCallCache | None
    ledger: UsageLedger = field(default_factory=UsageLedger)
    clients: dict[str, ModelClient] = field(default_factory=dict)
    requests: RunRequests = field(default_factory=RunRequests)
    """What each role's requests carry, shared by the role's clients."""
    throttling: list[LimiterState] = field(default_factory=list)
    """The endpoints' limiters as the run left them (set when the local backend finishes)."""
    players: dict[PolicyRole, Player] = field(default_factory=dict)
    """Each role's policy, resolved on the first episode (by name: in a Ray worker too)."""

    @classmethod
    def create(cls, config: RunConfig, run_dir: Path, requests: RunRequests | None = None) -> RunModels:
        """Clients for every configured role, with the run's cache, sending ``requests`` (default: what is
        known about each role's model beforehand).
        """
        cache = None
        if config.models.roles() and config.cache != "off":
            cache = ModelCallCache(
                Path(config.cache_path) if config.cache_path else run_dir / CACHE_FILE, config.cache
            )
        models = cls(config, cache, requests=requests or RunRequests.create(config))
        for role, model in config.models.roles().items():
            params = models.requests.params[role]
            models.clients[role] = ModelClient(model, role, cache, models.ledger, params=params)
        return models

    def limiters(self) -> list[EndpointLimiter]:
        """The running loop's limiter of each endpoint the clients call (roles sharing one share it)."""
        found: dict[int, EndpointLimiter] = {}
        for client in self.clients.values():
            limiter = client.limiter()
            found.setdefault(id(limiter), limiter)
        return list(found.values())

    def limiter_states(self) -> list[LimiterState]:
        """A snapshot of every endpoint's limiter (see :meth:`limiters`)."""
        return [limiter.state() for limiter in self.limiters()]

    async def aclose(self) -> None:
        """Close every client's connections and the cache's."""
        for client in self.clients.values():
            await client.aclose()
        if self.cache is not None:
            self.cache.close()

    def actors(
        self, plan: EpisodePlan, ledger: UsageLedger
    ) -> tuple[UserPolicy, AssistantPolicy, Judge | None]:
        """The user, the assistant and the judge of one episode, built by the policies the configuration
        names (by default: models where configured, else the oracle) from this episode's models.
        """
        config = self.config
        models: dict[str, ChatModel] = {
            role: EpisodeModel(client, plan.namespace, ledger) for role, client in self.clients.items()
        }
        configs = config.models.roles()
        if not self.players:
            self.players = {role: Player.resolve(role, config.policy(role)) for role in POLICY_ROLES}
        built: dict[PolicyRole, Any] = {}
        for role, player in self.players.items():
            names = MODEL_ROLES[role]
            context = PolicyContext(
                role=role,
                scenario=plan.scenario,
                run=plan.run,
                seed=plan.seed,
                models={name: models[name] for name in names if name in models},
                model_configs={name: configs[name] for name in names if name in configs},
                max_format_retries=config.protocol.max_format_retries,
            )
            built[role] = player.build(context)
        return built["user"], built["assistant"], built["judge"]


def check_policies(config: RunConfig) -> None:
    """Fail before anything runs (or any folder is made) when a role's policy cannot be found: an unknown
    name, a module that does not import, an attribute it lacks (what each factory returns is checked as
    the first episode builds it).
    """
    for role in POLICY_ROLES:
        Player.resolve(role, config.policy(role))
    if config.policy("user") == HUMAN:
        raise UserInputError(
            f"the '{HUMAN}' user is a person: play one scenario with 'pare play SCENARIO' (the same model "
            "and policy flags choose the assistant); 'pare run' plays without anyone at the keyboard"
        )


def check_credentials(config: RunConfig) -> None:
    """Fail before anything runs (or any folder is made) when a role's API key is not in the environment."""
    for role, model in config.models.roles().items():
        ModelClient(model, role).api_key()
