"""PARE as a verifiers environment (the ``verifiers`` extra): ``load_environment(...)`` returns a
``verifiers.v1.Env`` whose rollouts play PARE's own turn loop and whose rewards are PARE's verdict.

How PARE maps onto the library's parts:

* the **taskset** (:class:`PareTaskset`) has one task per scenario of a split (or the ids given), its data
  the scenario id and the world's seed (:class:`PareTaskData`);
* the **harness** (:class:`PareHarness`) is the program that plays the policy's seat. It runs in-process,
  as the library allows a harness to: it plays the scenario with PARE's turn loop
  (:func:`~pare.training.rollout.play_assistant`), the policy model as the assistant reached at the
  rollout's interception endpoint (so every call the assistant makes is on the trace, as the library
  records a program's calls), and the user played by the oracle or a configured model. The verdict and
  the trajectory are kept in ``trace.info["pare"]``;
* the **task's rewards** (:class:`PareTask`) read that verdict: ``success`` (weight 1), ``goal_rate``
  (weight 0, reported beside it) and the metric ``acceptance_rate``;
* the **environment** (:class:`PareEnv`) has one seat, ``assistant``, and plays one episode per rollout.

The library finds plugins by id among top-level modules: the id ``pare-bench`` is the module
:mod:`pare_bench`, which exports these classes. Importing this module needs the extra installed.
"""

from __future__ import annotations

import hashlib
from collections.abc import Iterator, Mapping, Sequence
from typing import Any, Literal

from openai import AsyncOpenAI
from pydantic import Field, ValidationError

from pare.agents.judge import ModelJudge
from pare.agents.models.client import ModelClient
from pare.agents.models.config import ModelConfig
from pare.errors import UserInputError
from pare.install import install_command
from pare.scenarios.library import get_scenario
from pare.training.rollout import play_assistant
from pare.training.setup import ORACLE, protocol_settings, scenario_pool

try:
    import verifiers.v1 as vf
except ImportError as error:  # pragma: no cover - depends on the install
    raise ImportError(
        f"pare.training.verifiers needs the verifiers library (the verifiers extra): "
        f"{install_command('verifiers')}"
    ) from error

ENV_ID = "pare-bench"
"""The id the library loads PARE by (``--env.taskset.id pare-bench``): the module :mod:`pare_bench`."""

PARE_INFO = "pare"
"""The key of ``trace.info`` under which the harness leaves the episode's verdict and trajectory."""


class PareTaskData(vf.TaskData):  # type: ignore[misc]
    """One scenario to play: its id and the world's seed."""

    scenario_id: str
    seed: int = 0


def _played(trace: Any) -> dict[str, Any]:
    """What the harness left on ``trace``; an error naming the problem when it left nothing."""
    played = trace.info.get(PARE_INFO)
    if not isinstance(played, dict):
        raise ValueError(f"the trace has no PARE episode under info[{PARE_INFO!r}]: the harness did not play")
    return played


class PareTask(vf.Task[PareTaskData, vf.State, vf.TaskConfig]):  # type: ignore[misc]
    """A scenario of PARE, scored by its verdict."""

    @property
    def key(self) -> str:
        """The scenario and its seed: the same task whatever position it has in the taskset."""
        return f"{self.data.scenario_id}@{self.data.seed}"

    @vf.reward(weight=1.0)  # type: ignore[untyped-decorator]
    async def success(self, trace: Any) -> float:
        """PARE's verdict: 1.0 when every goal was met and no side effect, else 0.0."""
        return 1.0 if _played(trace)["outcome"]["success"] else 0.0

    @vf.reward(weight=0.0)  # type: ignore[untyped-decorator]
    async def goal_rate(self, trace: Any) -> float:
        """The share of the scenario's goals met (weight 0: reported beside the reward)."""
        return float(_played(trace)["outcome"]["goal_rate"])

    @vf.metric  # type: ignore[untyped-decorator]
    async def acceptance_rate(self, trace: Any) -> float:
        """The share of the assistant's proposals the user accepted (0.0 when it proposed nothing)."""
        return float(_played(trace)["acceptance_rate"])


class PareTasksetConfig(vf.TasksetConfig):  # type: ignore[misc]
    """Which scenarios the taskset holds, and the seed their worlds are drawn from."""

    scenarios: list[str] | None = None
    """Scenario ids; None: the split's."""
    split: str | None = None
    """A split of the library (default ``smoke`` when no scenarios are given)."""
    seed: int = 0
    """Each scenario's world seed is derived from it and the scenario's id."""


def _row_seed(seed: int, scenario_id: str) -> int:
    digest = hashlib.sha256(f"{seed}:{scenario_id}".encode()).digest()
    return int.from_bytes(digest[:4], "big")


class PareTaskset(vf.Taskset[PareTask, PareTasksetConfig]):  # type: ignore[misc]
    """PARE's scenarios, one task each, sorted by id."""

    def load(self) -> Iterator[PareTask]:
        """One task per scenario of the configured split or ids."""
        for scenario_id in scenario_pool(self.config.scenarios, self.config.split):
            scenario = get_scenario(scenario_id)
            yield PareTask(
                PareTaskData(
                    id=scenario_id,
                    name=scenario_id,
                    description=scenario.title,
                    # The library wants a prompt to open a run with; PARE's harness writes the assistant's
                    # prompts itself (they exist only once the phone is built), so this one only names it.
                    prompt=f"PARE scenario {scenario_id}: {scenario.title}",
                    scenario_id=scenario_id,
                    seed=_row_seed(self.config.seed, scenario_id),
                ),
                self.config.task,
            )


class PareHarnessConfig(vf.HarnessConfig):  # type: ignore[misc]
    """Who plays the user and under which protocol the assistant's seat is played."""

    id: str = ENV_ID
    user: Literal["oracle"] | ModelConfig = ORACLE
    """The user: the oracle (the scenario's solution) or a model configuration."""
    protocol: str | dict[str, Any] | None = None
    """The turn protocol: a preset's name (``pare``, ``paper``) or a preset with overrides."""
    side_effects: bool = Field(default=True)
    """A change of the assistant's that no solution of the scenario makes fails the episode."""
    judge: ModelConfig | None = None
    """The model that judges free-text checks; None: each check's deterministic fallback."""


class PareHarness(vf.Harness[PareHarnessConfig]):  # type: ignore[misc]
    """Plays one PARE episode in-process, the policy model as the assistant through the interception."""

    APPENDS_SYSTEM_PROMPT = True  # PARE writes its own prompts; a task system prompt is not folded in
    EXECUTES_CODE = False
    NEEDS_CONTAINER = False

    async def launch(
        self,
        ctx: Any,
        trace: Any,
        runtime: Any,
        endpoint: str,
        secret: str,
        mcp_urls: dict[str, str],
        data: Any,
        tool_interception_url: str | None = None,
    ) -> Any:
        """Play ``data``'s scenario; the model calls go to ``endpoint`` with ``secret``, as the library
        requires of an in-process harness, and the verdict lands in ``trace.info``.
        """
        judge_client = ModelClient(self.config.judge, "judge") if self.config.judge is not None else None
        try:
            async with AsyncOpenAI(base_url=endpoint, api_key=secret, max_retries=0) as client:
                played = await play_assistant(
                    client,
                    ctx.model,
                    data.scenario_id,
                    seed=data.seed,
                    protocol=protocol_settings(self.config.protocol),
                    user=self.config.user,
                    side_effects=self.config.side_effects,
                    judge=ModelJudge(judge_client, judge_client.config.model) if judge_client else None,
                )
        finally:
            if judge_client is not None:
                await judge_client.aclose()
        trace.info[PARE_INFO] = {
            "scenario_id": data.scenario_id,
            "seed": data.seed,
            "outcome": played.outcome,
            "acceptance_rate": played.acceptance_rate(),
            "trajectory": played.trajectory,
        }
        return vf.ProgramResult(exit_code=0, stdout="", stderr="")


class PareEnvConfig(vf.EnvConfig):  # type: ignore[misc]
    """One seat, the assistant: the policy under training or evaluation. Its harness plays in this process,
    so its runtime is the local one (the library's default, a remote sandbox, would have nothing to run).
    """

    assistant: vf.AgentConfig = vf.AgentConfig(runtime=vf.SubprocessConfig())


class PareEnv(vf.Env[PareEnvConfig]):  # type: ignore[misc]
    """PARE's assistant task: one episode per rollout, scored by PARE's verdict."""

    async def run(self, task: PareTask, agents: Any) -> None:
        """Play the task's scenario with the assistant's seat."""
        await agents.assistant.run(task)


def load_environment(
    *,
    scenarios: Sequence[str] | None = None,
    split: str | None = None,
    user: Literal["oracle"] | ModelConfig | Mapping[str, Any] = ORACLE,
    protocol: str | Mapping[str, Any] | None = None,
    seed: int = 0,
    side_effects: bool = True,
    judge: ModelConfig | Mapping[str, Any] | None = None,
) -> PareEnv:
    """PARE's assistant task as a verifiers environment: the given ``scenarios`` (ids) or ``split``
    (default ``smoke``), the user played by the oracle or a model configuration (a
    :class:`~pare.agents.models.config.ModelConfig` or its fields), the turn ``protocol`` (a preset's
    name or a preset with overrides), each scenario's world seeded from ``seed``, free-text checks judged
    by ``judge`` (a model configuration; None: their deterministic fallbacks).

    Raises:
        UserInputError: an unknown scenario or split, or a protocol or model configuration that is not
            valid.
    """
    scenario_pool(scenarios, split)  # unknown ids or splits fail here, by name
    protocol_settings(dict(protocol) if isinstance(protocol, Mapping) else protocol)
    try:
        config = PareEnvConfig(
            taskset={
                "id": ENV_ID,
                "scenarios": list(scenarios) if scenarios is not None else None,
                "split": split,
                "seed": seed,
            },
            assistant={
                "harness": {
                    "id": ENV_ID,
                    "user": dict(user) if isinstance(user, Mapping) else user,
                    "protocol": dict(protocol) if isinstance(protocol, Mapping) else protocol,
                    "side_effects": side_effects,
                    "judge": dict(judge) if isinstance(judge, Mapping) else judge,
                }
            },
        )
    except ValidationError as error:
        raise UserInputError(f"the verifiers environment's settings: {error}") from None
    return PareEnv(config)
