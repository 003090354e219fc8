"""One calibration case played in its scenario's world: the oracle up to the proposal, then the user under
test decides it.

The scenario's oracle plays both roles until the moment its solution makes the case's proposal (its user
steps, and any earlier proposal accepted and carried out), so the world is what a real episode would show
then. The assistant then proposes the case's text instead of the solution's, and the user under test takes
over: it sees the phone as it is, the proposal pending, and may look things up (open an app, read an item)
for at most ``max_steps`` actions, within the proposal's lifetime, before it answers. Its answer ends the
case; nothing of the proposal is carried out (the decision is what is measured). The episode loop, the
environment and the turn protocol are a run's own (:func:`~pare.bench.episode.arun_episode`).
"""

from __future__ import annotations

from dataclasses import dataclass

from pare.agents.policy import (
    ASSISTANT_WAIT,
    DEFAULT_BUDGET,
    SEND_MESSAGE,
    WAIT,
    Action,
    AssistantPolicy,
    Ending,
    Task,
    TurnBudget,
    UserPolicy,
)
from pare.bench.calibration.cases import CalibrationCase
from pare.bench.episode import EpisodeResult, EpisodeSettings, arun_episode
from pare.env import AssistantObservation, Environment, ToolResult, UserView
from pare.results.calibration import Decision
from pare.scenarios.oracle import OracleAssistant, OracleUser

ANSWERS = frozenset({"accept_proposal", "reject_proposal"})
MAX_STEPS = 6
"""The user's actions on a case, its answer included, by default: enough to open an app and an item and
come back; the proposal's lifetime (``protocol.proposal_ttl_turns``) may end it sooner."""
NOTHING_DONE = "Understood."
"""What the assistant reports after an accepted case: nothing is carried out."""


class CaseUser(UserPolicy):
    """The oracle user until the case's proposal is pending, then the user under test, for a bounded
    number of actions or until it answers (or the proposal is withdrawn).
    """

    name = "calibration_user"

    def __init__(self, case: CalibrationCase, tested: UserPolicy, max_steps: int = MAX_STEPS) -> None:
        self.case = case
        self.oracle = OracleUser(case.scenario, case.solution)
        self.tested = tested
        self.max_steps = max_steps
        self.actions: list[str] = []
        """The tools the user under test called, from the proposal on."""
        self.handed_over = False
        self.done = False
        self.env: Environment | None = None
        self.budget: TurnBudget = DEFAULT_BUDGET

    def start(self, env: Environment, budget: TurnBudget = DEFAULT_BUDGET) -> None:
        """Start the oracle user; the user under test starts when the proposal arrives."""
        self.oracle.start(env, budget)
        self.env, self.budget = env, budget

    async def step(self, view: UserView, previous: ToolResult | None) -> Action:
        """The oracle's step before the proposal; the tested user's after it; waiting once it is over."""
        if self.done:
            return Action(WAIT)
        if not self.handed_over:
            if view.pending_proposal != self.case.proposal:
                return await self.oracle.step(view, previous)
            if self.env is None:
                raise RuntimeError("CaseUser.start() was not called")
            self.handed_over = True
            self.tested.start(self.env, self.budget)
            previous = None  # the oracle's last action is not the tested user's
        elif view.pending_proposal is None:  # withdrawn unanswered
            self.done = True
            return Action(WAIT)
        action = await self.tested.step(view, previous)
        self.actions.append(action.tool)
        if action.tool in ANSWERS or len(self.actions) >= self.max_steps:
            self.done = True
        return action

    def finish(self, ending: Ending, previous: ToolResult | None, notifications: list[str]) -> str | None:
        """The tested user's closing, when it took over."""
        return self.tested.finish(ending, previous, notifications) if self.handed_over else None


class CaseAssistant(AssistantPolicy):
    """The oracle assistant of the case's solution, which makes the case's proposal in place of the
    solution's target proposal and then only waits; an accepted case is reported without doing anything.
    """

    name = "calibration_assistant"

    def __init__(self, case: CalibrationCase) -> None:
        self.case = case
        self.oracle = OracleAssistant(case.scenario, case.solution)
        self.proposed = False

    def start(self, env: Environment, budget: TurnBudget = DEFAULT_BUDGET) -> None:
        """Start the oracle assistant."""
        self.oracle.start(env, budget)

    async def observe(self, observation: AssistantObservation | None, previous: ToolResult | None) -> Action:
        """The oracle's observe step, its target proposal replaced by the case's; then wait."""
        if self.proposed:
            return Action(ASSISTANT_WAIT)
        at_target = self.oracle.next_intervention == self.case.target
        action = await self.oracle.observe(observation, previous)
        if at_target and action.tool == SEND_MESSAGE:
            self.proposed = True
            return Action(SEND_MESSAGE, {"content": self.case.proposal})
        return action

    async def execute(self, task: Task | None, previous: ToolResult | None) -> Action:
        """Carry out an earlier (oracle) proposal as the oracle does; report the case's at once."""
        if self.proposed:
            return Action(SEND_MESSAGE, {"content": NOTHING_DONE})
        return await self.oracle.execute(task, previous)


@dataclass(frozen=True, slots=True)
class CaseOutcome:
    """What the user under test did with the case's proposal."""

    decision: Decision
    looked: int
    """Actions the user took before answering (or before giving up): looking things up."""
    reason: str
    """The reason given with the answer."""
    result: EpisodeResult


async def play_case(
    case: CalibrationCase, tested: UserPolicy, settings: EpisodeSettings, *, max_steps: int = MAX_STEPS
) -> CaseOutcome:
    """Play ``case`` with ``tested`` deciding its proposal (see the module's docstring)."""
    user = CaseUser(case, tested, max_steps)
    result = await arun_episode(case.scenario, user, CaseAssistant(case), settings, side_effects=False)
    proposal = next(
        (p for p in result.env.agent_ui.state.proposals if p.content == case.proposal and user.handed_over),
        None,
    )
    decision: Decision
    if proposal is None:
        decision = "not_reached"
    elif proposal.status == "accepted":
        decision = "accept"
    elif proposal.status == "rejected":
        decision = "reject"
    else:
        decision = "no_answer"
    answered = decision in ("accept", "reject")
    looked = sum(1 for tool in user.actions if tool not in ANSWERS and tool != WAIT)
    reason = proposal.reason if proposal is not None and answered else ""
    return CaseOutcome(decision, looked, reason, result)
