"""The self-test gate: every scenario must prove that it can be solved and that it cannot be faked.

Four deterministic runs per scenario, through the same turn loop as a real run:

* ``oracle`` — the oracle user and the oracle assistant: must succeed, with no failed oracle call and no
  failed scheduled event;
* ``nothing`` — a silent user and a silent assistant: must fail;
* ``user_alone`` — the oracle user's own steps with a silent assistant: must fail;
* ``unrelated`` — the oracle user and an assistant that proposes and does something unrelated: must fail.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Iterable
from dataclasses import dataclass, field

from pare.agents.policy import AssistantPolicy, SilentAssistant, SilentUser, UserPolicy
from pare.bench.episode import EpisodeResult, EpisodeSettings, run_episode
from pare.errors import UserInputError
from pare.scenarios.model import Scenario
from pare.scenarios.oracle import OracleAssistant, OracleUser, UnrelatedAssistant

PolicyPair = Callable[[Scenario], tuple[UserPolicy, AssistantPolicy]]

RUNS: dict[str, tuple[PolicyPair, bool]] = {
    "oracle": (lambda s: (OracleUser(s), OracleAssistant(s)), True),
    "nothing": (lambda s: (SilentUser(), SilentAssistant()), False),
    "user_alone": (lambda s: (OracleUser(s), SilentAssistant()), False),
    "unrelated": (lambda s: (OracleUser(s), UnrelatedAssistant(s)), False),
}
"""Each self-test run: how to make its two policies, and whether the scenario must succeed."""


@dataclass(frozen=True, slots=True)
class RunVerdict:
    """One self-test run of one scenario."""

    run: str
    expected_success: bool
    success: bool | None
    """``None`` when the run could not be played at all."""
    problems: tuple[str, ...] = ()

    @property
    def ok(self) -> bool:
        """Whether the run went as the gate demands."""
        return not self.problems and self.success == self.expected_success


@dataclass(frozen=True, slots=True)
class ScenarioVerdict:
    """The gate's verdict on one scenario."""

    scenario_id: str
    runs: tuple[RunVerdict, ...]
    seconds: float
    details: dict[str, EpisodeResult] = field(default_factory=dict, compare=False, repr=False)

    @property
    def ok(self) -> bool:
        """Whether every run went as demanded."""
        return all(run.ok for run in self.runs)

    def breaches(self) -> list[str]:
        """One line per broken demand."""
        lines: list[str] = []
        for run in self.runs:
            if run.ok:
                continue
            if run.problems:
                lines.extend(f"{self.scenario_id} [{run.run}]: {problem}" for problem in run.problems)
            else:
                wanted = "succeed" if run.expected_success else "fail"
                lines.append(f"{self.scenario_id} [{run.run}]: should {wanted} but did not")
        return lines


def check_scenario(scenario: Scenario, settings: EpisodeSettings | None = None) -> ScenarioVerdict:
    """Run the four self-test runs on ``scenario``."""
    began = time.perf_counter()
    verdicts = []
    details: dict[str, EpisodeResult] = {}
    for name, (make, expected) in RUNS.items():
        user, assistant = make(scenario)
        try:
            result = run_episode(scenario, user, assistant, settings)
        except UserInputError as error:
            verdicts.append(RunVerdict(name, expected, None, (str(error),)))
            continue
        details[name] = result
        problems = _oracle_problems(result) if name == "oracle" else []
        if expected and not result.success:
            problems.extend(
                f"check failed: {check.goal}[{check.index}] {check.detail}"
                for check in result.outcome.failures()
            )
        verdicts.append(RunVerdict(name, expected, result.success, tuple(problems)))
    return ScenarioVerdict(scenario.id, tuple(verdicts), time.perf_counter() - began, details)


def _oracle_problems(result: EpisodeResult) -> list[str]:
    problems = []
    for entry in result.env.log:
        if entry.actor in ("user", "assistant") and not entry.ok and not entry.injected_failure:
            problems.append(
                f"oracle {entry.actor} call #{entry.index} {entry.app}.{entry.tool} failed: {entry.error}"
            )
    problems.extend(
        f"scheduled event '{entry.event_id}' failed: {entry.error}" for entry in result.env.failed_events()
    )
    proposals = result.env.agent_ui.state.proposals
    if not proposals:
        problems.append("the oracle assistant never proposed (its intervention's condition never held)")
    problems.extend(
        f"proposal {p.proposal_id} ended {p.status}, not accepted"
        for p in proposals
        if p.status != "accepted"
    )
    return problems


def check_scenarios(
    scenarios: Iterable[Scenario], settings: EpisodeSettings | None = None
) -> list[ScenarioVerdict]:
    """The gate over several scenarios."""
    return [check_scenario(scenario, settings) for scenario in scenarios]
