"""Many episodes: plan them, play them concurrently, store each as it finishes, resume what is missing.

The unit of work is one episode: a scenario, a run index (1 to k) and the configuration. Episodes run as
asyncio tasks under a bound (model calls are the bottleneck, the simulation itself takes well under a
millisecond per turn), or as Ray tasks on a cluster; either way the driver writes every finished episode
to the run's store at once, so a killed run loses nothing it finished.

Failures are sorted by who is to blame:

* the model's behaviour (malformed answers, wrong actions, a prompt beyond its context) is part of the
  episode and judged by its checks;
* the infrastructure (a provider down past every retry) makes the episode run again, up to
  ``episode_retries`` times, then it is stored as *failed*: missing coverage, never a model failure;
* a replay cache that lacks a call, or an error inside PARE, is stored as failed at once (running it
  again would fail the same way);
* a mistake in the configuration (no API key, unknown model, refused credentials) stops the whole run
  at the first episode that meets it: every other episode would fail the same way.
"""

from __future__ import annotations

import asyncio
import dataclasses
import heapq
import json
import math
import time
import traceback
from collections import deque
from collections.abc import Awaitable, Callable, Iterable, Mapping, Sequence
from contextlib import ExitStack
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any, Protocol

from pare.agents.models.cache import ModelCallCache
from pare.agents.models.client import ModelClient
from pare.agents.models.config import ModelConfig
from pare.agents.models.ledger import UsageLedger
from pare.agents.models.limiter import EndpointLimiter, LimiterState
from pare.agents.models.request_params import RequestParams
from pare.agents.models.types import ChatMessage, Completion
from pare.agents.policy import AssistantPolicy, UserPolicy
from pare.bench import collector
from pare.bench.episode import arun_episode
from pare.bench.policies import HUMAN, MODEL_ROLES, POLICY_ROLES, Player, PolicyContext, PolicyRole
from pare.bench.run_requests import Learned, RunRequests, learned_refusals
from pare.bench.runconfig import RunConfig
from pare.bench.store import CACHE_FILE, RunStore
from pare.errors import CacheMiss, RunFailure, UserInputError, first_error
from pare.results.records import EpisodeRecord, Failure, FailureKind, summarize
from pare.results.run_folder import scenario_hash, trajectory_path
from pare.scenarios.library import library, load_scenarios, select
from pare.scenarios.model import Scenario

if TYPE_CHECKING:  # imported where a run has models: an oracle run never loads the actors or the prompts
    from pare.agents.llm import ChatModel
    from pare.scenarios.checks import Judge

RETRY_PAUSE_S = 2.0
"""Pause before an episode that failed for infrastructure reasons runs again (doubling each time)."""
REPORT_INTERVAL_S = 0.2
"""At most this long between an episode being stored and the progress display counting it."""


# -- planning ---------------------------------------------------------------------------------------------
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


def select_scenarios(config: RunConfig) -> dict[str, Scenario]:
    """The scenarios the configuration names, by id (an empty selection is an error)."""
    selection = config.scenarios
    pool = load_scenarios(selection.paths) if selection.paths else list(library().values())
    chosen = select(
        pool,
        ids=selection.ids,
        split=selection.split,
        apps=selection.apps,
        tags=selection.tags,
        difficulty=selection.difficulty,
        kinds=selection.kinds,
    )
    if not chosen:
        raise UserInputError("no scenario matches the selection; see 'pare scenarios list' for what there is")
    return {scenario.id: scenario for scenario in sorted(chosen, key=lambda s: s.id)}


def plan_episodes(
    config: RunConfig, scenarios: Mapping[str, Scenario], hashes: Mapping[str, str] | None = None
) -> list[EpisodePlan]:
    """Every episode of the run, run-major (all scenarios' run 1, then run 2, ...). The runner plays
    scenarios it has not seen yet in this order, so run 1 of every scenario comes first, then the
    remaining runs longest expected first (see :class:`LongestFirst`).

    ``hashes`` are the scenarios' content hashes when already known (the store computes them when it
    opens: hashing the library takes about a tenth of a second); the missing ones are computed.
    """
    known = hashes or {}
    hashes = {
        scenario_id: known.get(scenario_id) or scenario_hash(scenario)
        for scenario_id, scenario in scenarios.items()
    }
    return [
        EpisodePlan(scenario, run, config.episode_seed(scenario_id, run), hashes[scenario_id])
        for run in range(1, config.runs + 1)
        for scenario_id, scenario in sorted(scenarios.items())
    ]


# -- models -----------------------------------------------------------------------------------------------
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


# -- one episode ------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class EpisodeOutput:
    """A finished (or failed) episode, ready for the store."""

    record: EpisodeRecord
    trajectory: str | None
    """The trajectory file's JSON text, serialised where the episode was played (so a value no file can
    hold fails this episode, not the run)."""
    learned: Learned = field(default_factory=dict)
    """Parameter refusals the episode's clients learned, by role (set for an episode played apart)."""


def _base_fields(plan: EpisodePlan) -> dict[str, Any]:
    scenario = plan.scenario
    return {
        "scenario_id": scenario.id,
        "run": plan.run,
        "scenario_hash": plan.scenario_hash,
        "seed": plan.seed,
        "apps": list(scenario.all_apps),
        "tags": list(scenario.tags),
        "difficulty": scenario.difficulty,
        "kind": scenario.kind,
    }


def failed_output(plan: EpisodePlan, kind: FailureKind, message: str, attempts: int) -> EpisodeOutput:
    """The record of an episode that could not be run."""
    record = EpisodeRecord(
        **_base_fields(plan),
        status="failed",
        attempts=attempts,
        failure=Failure(kind=kind, message=message),
    )
    return EpisodeOutput(record, None)


async def play_episode(
    plan: EpisodePlan, config: RunConfig, models: RunModels, attempt: int = 1
) -> EpisodeOutput:
    """Play one episode and summarise it. Raises :class:`RunFailure` for infrastructure failures (the
    caller retries) and :class:`UserInputError` for configuration mistakes (the caller stops the run);
    any other failure becomes a failed record.
    """
    ledger = UsageLedger()
    started = time.perf_counter()
    try:
        user, assistant, judge = models.actors(plan, ledger)
        result = await arun_episode(
            plan.scenario, user, assistant, config.episode_settings(plan.seed), judge=judge
        )
    except CacheMiss as error:  # before UserInputError, its base: a miss is this episode's problem only
        return failed_output(plan, "cache_miss", str(error), attempt)
    except (RunFailure, UserInputError):
        raise
    except Exception as error:  # a bug in PARE: keep the run going, keep the evidence
        detail = "".join(traceback.format_exception(error, limit=-8)).strip()
        return failed_output(plan, "internal_error", detail, attempt)
    trajectory = {
        "format": 1,
        "label": config.label(),
        "run": plan.run,
        "seed": plan.seed,
        "scenario_hash": plan.scenario_hash,
        **result.to_dict(),
    }
    try:
        # Strict JSON (no NaN or Infinity) in valid UTF-8: every file of the run stays readable.
        text = json.dumps(trajectory, ensure_ascii=False, allow_nan=False, separators=(",", ":"))
        text.encode("utf-8")  # the record's text comes from the same result, so it is checked too
        record = EpisodeRecord(
            **_base_fields(plan),
            status="complete",
            attempts=attempt,
            trajectory=trajectory_path(plan.scenario.id, plan.run),
            wall_s=round(time.perf_counter() - started, 3),
            **summarize(result, usage=ledger.roles()),
        )
    except (ValueError, UnicodeEncodeError) as error:  # a bug in PARE: something let such a value through
        detail = "".join(traceback.format_exception(error, limit=-8)).strip()
        return failed_output(plan, "internal_error", f"the episode cannot be stored: {detail}", attempt)
    return EpisodeOutput(record, text)


async def play_with_retries(
    plan: EpisodePlan,
    play: Callable[[EpisodePlan, int], Awaitable[EpisodeOutput]],
    retries: int,
    pause_s: float | None = None,
) -> EpisodeOutput:
    """Play ``plan``, rerunning it after infrastructure failures (pausing ``pause_s``, default
    :data:`RETRY_PAUSE_S`, doubled each time); the last failure becomes a record.
    """
    pause = RETRY_PAUSE_S if pause_s is None else pause_s
    attempt = 1
    while True:
        try:
            return await play(plan, attempt)
        except RunFailure as error:
            if attempt > retries:
                return failed_output(plan, "provider_unavailable", str(error), attempt)
            await asyncio.sleep(pause * 2 ** (attempt - 1))
            attempt += 1


# -- progress ---------------------------------------------------------------------------------------------
class ProgressSink(Protocol):
    """Told about the run as it goes (the command line draws a progress bar from it)."""

    def started(self, total: int, done: int, label: str) -> None:
        """The run begins: ``total`` episodes, ``done`` of them finished in earlier sessions."""

    def finished(self, record: EpisodeRecord) -> None:
        """One more episode was stored."""

    def stopped(self) -> None:
        """The run ended (finished, failed or interrupted)."""

    def throttling(self, endpoints: Sequence[LimiterState]) -> None:
        """The model endpoints' limiters now (told a few times a second while models are called)."""


class NoProgress:
    """A progress sink that shows nothing."""

    def started(self, total: int, done: int, label: str) -> None:
        """Nothing to show."""

    def finished(self, record: EpisodeRecord) -> None:
        """Nothing to show."""

    def stopped(self) -> None:
        """Nothing to show."""

    def throttling(self, endpoints: Sequence[LimiterState]) -> None:
        """Nothing to show."""


# -- the order of episodes --------------------------------------------------------------------------------
class LongestFirst:
    """The episodes still to play, longest expected first.

    A run's wall time is set by its tail: a long episode started last keeps the run going while the other
    slots sit idle. Runs of one scenario take similar times, so once one run of a scenario has finished
    (in this session or an earlier one) its other runs are expected to take as long, and the longest go
    first. Scenarios not seen yet go before all others, in plan order, to learn their length early.

    The scenarios wait in a heap keyed by (minus the expected seconds, the plan index of the scenario's
    next episode), so a pick costs a logarithm of the scenarios rather than a pass over all of them. A key
    that changed (a run finished, an episode was picked) is pushed anew; the old entry is recognised as
    stale when it reaches the top and dropped.
    """

    def __init__(self, plans: Sequence[EpisodePlan], finished: Iterable[EpisodeRecord] = ()) -> None:
        # per scenario, its pending episodes in plan order; a pick compares scenarios, not episodes
        self._pending: dict[str, deque[tuple[int, EpisodePlan]]] = {}
        for index, plan in enumerate(plans):
            self._pending.setdefault(plan.scenario.id, deque()).append((index, plan))
        self._count = len(plans)
        self._seconds: dict[str, list[float]] = {}
        self._heap: list[tuple[float, int, str]] = []
        for record in finished:
            self.learn(record)
        self._heap.extend(self._entry(name) for name in self._pending)
        heapq.heapify(self._heap)

    def __len__(self) -> int:
        return self._count

    def learn(self, record: EpisodeRecord) -> None:
        """Remember how long a finished episode took."""
        if record.complete:
            self._seconds.setdefault(record.scenario_id, []).append(record.wall_s)
            if record.scenario_id in self._pending:
                heapq.heappush(self._heap, self._entry(record.scenario_id))

    def expected_seconds(self, scenario_id: str) -> float:
        """The mean time of the scenario's finished episodes; infinite while none has finished."""
        seen = self._seconds.get(scenario_id)
        return sum(seen) / len(seen) if seen else math.inf

    def _entry(self, scenario_id: str) -> tuple[float, int, str]:
        """The scenario's heap entry now: the longest expected first, the earliest planned among equals."""
        return (-self.expected_seconds(scenario_id), self._pending[scenario_id][0][0], scenario_id)

    def pop(self) -> EpisodePlan:
        """The next episode to play: the longest expected, the earliest planned among equals."""
        while True:
            entry = heapq.heappop(self._heap)
            scenario_id = entry[2]
            if scenario_id in self._pending and entry == self._entry(scenario_id):
                break  # else stale: the scenario's key changed since this entry was pushed
        queue = self._pending[scenario_id]
        _, plan = queue.popleft()
        self._count -= 1
        if queue:
            heapq.heappush(self._heap, self._entry(scenario_id))
        else:
            del self._pending[scenario_id]
        return plan


# -- many episodes ----------------------------------------------------------------------------------------
@dataclass
class RunSummary:
    """What one ``pare run`` session did."""

    path: Path
    label: str
    planned: int
    skipped: int
    records: list[EpisodeRecord]
    """The records written in this session."""
    seconds: float
    throttling: list[LimiterState] = field(default_factory=list)
    """Each model endpoint's limiter at the end of the session: its rate-limit answers (429), the cuts of
    its concurrency, and the time calls waited because of rate limiting (empty for oracle and Ray runs)."""

    @property
    def complete(self) -> int:
        """Episodes finished in this session."""
        return sum(record.complete for record in self.records)

    @property
    def failed(self) -> list[EpisodeRecord]:
        """Episodes stored as failed (missing coverage) in this session."""
        return [record for record in self.records if not record.complete]


def play_apart(
    plan: EpisodePlan, config: RunConfig, run_dir: Path, learned: Learned | None = None
) -> tuple[str, EpisodeOutput | str]:
    """One episode played on its own, in a process other than the run's (a Ray task, a worker process):
    with its own model clients, knowing the parameter refusals the run ``learned`` so far, retrying
    infrastructure failures like the local backend. Returns ``("ok", output)`` (with the refusals its
    clients learned), or ``("error", message)`` for a mistake in the configuration (returned, not
    raised, so the run raises it with PARE's own message rather than the executor's wrapper).
    """

    async def play() -> EpisodeOutput:
        models = RunModels.create(config, run_dir, RunRequests.create(config, learned))
        try:

            async def attempt(plan: EpisodePlan, number: int) -> EpisodeOutput:
                return await play_episode(plan, config, models, number)

            output = await play_with_retries(plan, attempt, config.episode_retries)
            return dataclasses.replace(output, learned=models.requests.learned())
        finally:
            await models.aclose()

    try:
        return ("ok", asyncio.run(play()))
    except UserInputError as error:
        return ("error", str(error))


def report_written(store: RunStore, progress: ProgressSink, written: list[EpisodeRecord]) -> None:
    """Count as finished the episodes whose lines the store wrote since the last call (an episode handed
    to the store is not finished yet: a run killed before its line is written plays it again).
    """
    for record in store.committed():
        written.append(record)
        progress.finished(record)


async def run_local(
    plans: Sequence[EpisodePlan],
    config: RunConfig,
    models: RunModels,
    store: RunStore,
    progress: ProgressSink,
) -> list[EpisodeRecord]:
    """Play ``plans`` on ``config.concurrency`` asyncio workers, storing each episode as it ends."""
    queue = LongestFirst(plans, store.records.values())
    written: list[EpisodeRecord] = []

    async def play(plan: EpisodePlan, attempt: int) -> EpisodeOutput:
        return await play_episode(plan, config, models, attempt)

    async def worker() -> None:
        while queue:
            plan = queue.pop()
            output = await play_with_retries(plan, play, config.episode_retries)
            queue.learn(output.record)
            store.append(output.record, output.trajectory)
            report_written(store, progress, written)
            # an episode without model calls never suspends: yield, so the loop sees Ctrl-C between them
            await asyncio.sleep(0)

    async def reporter() -> None:
        # episodes are stored a moment after they are handed over: report them also while no other
        # episode finishes (a model-backed episode can take minutes)
        while True:
            await asyncio.sleep(REPORT_INTERVAL_S)
            report_written(store, progress, written)
            if models.clients:
                progress.throttling(models.limiter_states())

    # every role's settings reach its endpoint's limiter before the first call (the strictest applies)
    models.limiters()
    ticker = asyncio.create_task(reporter())
    try:
        async with asyncio.TaskGroup() as group:
            for _ in range(min(config.concurrency, len(plans))):
                group.create_task(worker())
        store.flush()
        report_written(store, progress, written)
    except BaseExceptionGroup as errors:
        raise first_error(errors) from None
    finally:
        ticker.cancel()
        models.throttling = models.limiter_states()
        await models.aclose()
    return written


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


def run_benchmark(
    config: RunConfig,
    *,
    progress: ProgressSink | None = None,
    sweep_point: Mapping[str, Any] | None = None,
) -> RunSummary:
    """Run (or resume) the benchmark ``config`` describes; return what this session did."""
    progress = progress or NoProgress()
    with ExitStack() as stack:
        # Loading and planning make objects that live as long as the run: no collection while they are
        # made, and none of them walked by the collections made while the episodes play (collector.py).
        with collector.paused():
            scenarios = select_scenarios(config)
            check_policies(config)
            check_credentials(config)
            run_dir = config.output_dir()
            started = time.perf_counter()
            store = stack.enter_context(RunStore.open(run_dir, config, scenarios, sweep_point=sweep_point))
            plans = plan_episodes(config, scenarios, store.hashes)
            todo = [plan for plan in plans if not store.done(plan.key)]
        progress.started(len(plans), len(plans) - len(todo), config.label())
        with collector.long_lived_frozen():
            try:
                requests = RunRequests.create(config, learned_refusals(store.manifest))
                requests.record_in(store)
                throttling: list[LimiterState] = []
                if config.backend == "ray":
                    from pare.bench.ray_backend import run_ray

                    written = run_ray(todo, config, store, progress, requests)
                else:
                    models = RunModels.create(config, run_dir, requests)
                    written = asyncio.run(run_local(todo, config, models, store, progress))
                    throttling = models.throttling
            finally:
                progress.stopped()
    return RunSummary(
        path=run_dir,
        label=config.label(),
        planned=len(plans),
        skipped=len(plans) - len(todo),
        records=written,
        seconds=time.perf_counter() - started,
        throttling=throttling,
    )
