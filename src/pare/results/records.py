"""One line per episode in a run's store: what the metrics need, derived once from the trajectory
(:func:`summarize`, a pure function of :class:`~pare.results.trajectory.Trajectory`).

A record is written when an episode finishes (``status: complete``) or when it could not be run for
reasons outside the model's behaviour (``status: failed``: the provider stayed down, a replay cache
lacked a call, PARE itself broke). Reports read only these lines; the full trajectory of a complete
episode sits in its own file, named by ``trajectory``.

Proposals are classified the way the paper's decision analysis does it. The *decision* is the user's
first step after the proposal reached them: ``accept`` or ``reject`` when that step answered it,
``gather_context`` when the user did anything else first (opened an app, waited, ...), ``truncated``
when the episode ended before the user took another step. The *resolution* is what finally became of
it: ``accepted``, ``rejected``, ``expired`` (unanswered for ``proposal_ttl_turns`` turns), or
``truncated`` (still pending when the episode ended).
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from typing import Any, Literal

from pydantic import BaseModel, ConfigDict, Field, field_validator

from pare.agents.models.ledger import RoleUsage
from pare.agents.policy import SEND_MESSAGE
from pare.apps.harm import IRREVERSIBLE, tool_harm
from pare.results.trajectory import (  # the faults are kept in the trajectory, and summed here
    ANSWERS,
    SideEffectRecord,
    Trajectory,
)
from pare.results.trajectory import (
    FAULT_KINDS as FAULT_KINDS,
)
from pare.results.trajectory import (
    FaultKind as FaultKind,
)
from pare.results.trajectory import (
    SimulatorFault as SimulatorFault,
)

RECORD_FORMAT = 1

Decision = Literal["accept", "reject", "gather_context", "truncated"]
Resolution = Literal["accepted", "rejected", "expired", "truncated"]
EpisodeStatus = Literal["complete", "failed"]
FailureKind = Literal["provider_unavailable", "cache_miss", "internal_error", "not_regradable"]

DECISIONS: tuple[Decision, ...] = ("accept", "reject", "gather_context", "truncated")
RESOLUTIONS: tuple[Resolution, ...] = ("accepted", "rejected", "expired", "truncated")


class ProposalRecord(BaseModel):
    """One proposal the assistant made and what the user did with it."""

    model_config = ConfigDict(extra="forbid", frozen=True, allow_inf_nan=False)

    proposal_id: str
    turn: int = Field(description="Turn in which the assistant proposed.")
    content: str
    decision: Decision
    resolution: Resolution
    answered_turn: int | None = Field(default=None, description="Turn of the accept or reject, if any.")
    user_steps_before_answer: int = Field(
        default=0, description="User steps between the proposal and its answer (or its end)."
    )


class PreviousVerdict(BaseModel):
    """What a re-graded episode's record said before ``pare regrade`` judged it again."""

    model_config = ConfigDict(extra="forbid", frozen=True, allow_inf_nan=False)

    success: bool
    goals: dict[str, bool] = Field(default_factory=dict)
    side_effects: int = 0
    scenario_hash: str = Field(description="The scenario version the episode was judged by.")

    @classmethod
    def of(cls, record: EpisodeRecord) -> PreviousVerdict:
        """The verdict ``record`` holds."""
        return cls(
            success=record.success,
            goals=dict(record.goals),
            side_effects=record.side_effects,
            scenario_hash=record.scenario_hash,
        )


class Failure(BaseModel):
    """Why an episode could not be run (missing coverage, not a failure of the model)."""

    model_config = ConfigDict(extra="forbid", frozen=True, allow_inf_nan=False)

    kind: FailureKind
    message: str


class EpisodeRecord(BaseModel):
    """The summary line of one episode (scenario x run) of one configuration."""

    model_config = ConfigDict(extra="forbid", frozen=True, allow_inf_nan=False)

    format: int = RECORD_FORMAT
    scenario_id: str

    @field_validator("format")
    @classmethod
    def _known_format(cls, value: int) -> int:
        if value != RECORD_FORMAT:
            raise ValueError(
                f"record format {value}, but this PARE reads format {RECORD_FORMAT}; read it with the PARE "
                "version that wrote it"
            )
        return value

    run: int = Field(ge=1, description="Run index, 1 to k.")
    status: EpisodeStatus
    attempts: int = Field(default=1, ge=1, description="Times the episode was started in this session.")
    failure: Failure | None = None
    scenario_hash: str = Field(description="Content hash of the scenario the episode ran.")
    seed: int = Field(description="The episode environment's seed.")
    apps: list[str] = Field(default_factory=list)
    tags: list[str] = Field(default_factory=list)
    difficulty: str = ""
    kind: Literal["proposal", "no_proposal"] | None = Field(
        default=None,
        description="The scenario's kind: whether the right move was to propose (None in records written "
        "before kinds were recorded).",
    )
    # the verdict and the counts below are meaningful for complete episodes only
    success: bool = False
    goals: dict[str, bool] = Field(default_factory=dict)
    goal_rate: float = 0.0
    user_did_work: bool = Field(
        default=False,
        description="Failed, and the user made by hand something a goal wanted from the assistant.",
    )
    side_effects: int = Field(
        default=0,
        description="Changes the assistant made that no solution of the scenario makes, and details it "
        "invented (any fails the episode; the trajectory's outcome names them).",
    )
    invented_details: int = Field(
        default=0,
        description="Of the side effects, the details (time, date, amount, phone, link, address) the "
        "assistant wrote into the apps that nothing in its world gives (pare.scenarios.invented).",
    )
    irreversible_actions: int | None = Field(
        default=None,
        description="The assistant's successful calls of irreversible tools (a sent message, a deletion; "
        "pare.apps.harm), right or wrong (None in records written before harm was recorded).",
    )
    wrong_irreversible_actions: int | None = Field(
        default=None,
        description="Of those calls, the ones that made a side effect: an irreversible change no solution "
        "of the scenario makes (None in records written before harm was recorded).",
    )
    simulator_faults: list[SimulatorFault] = Field(
        default_factory=list,
        description="What the user simulator did wrong on its own (empty in records written before faults "
        "were recorded).",
    )
    turns: int = 0
    ended: str = ""
    observe_turns: int = Field(default=0, description="Turns in which the assistant acted in observe mode.")
    proposals: list[ProposalRecord] = Field(default_factory=list)
    read_actions: int = Field(default=0, description="The assistant's read-only tool calls (both modes).")
    observe_read_actions: int = 0
    write_actions: int = Field(default=0, description="The assistant's app writes (execute mode).")
    user_actions: int = Field(default=0, description="The user's steps (waits included).")
    failed_steps: dict[str, int] = Field(
        default_factory=dict, description="Steps per role whose action failed or was malformed."
    )
    format_errors: dict[str, int] = Field(
        default_factory=dict, description="Malformed model answers per role (each retried)."
    )
    usage: dict[str, RoleUsage] = Field(default_factory=dict, description="Model usage per role.")
    trajectory: str | None = Field(default=None, description="The trajectory file, relative to the run.")
    regraded_from: PreviousVerdict | None = Field(
        default=None, description="In a re-graded run (pare regrade): the verdict the original run gave."
    )
    wall_s: float = Field(default=0.0, description="Wall-clock seconds the episode took (not simulated).")

    @property
    def key(self) -> tuple[str, int]:
        """What identifies the episode within its configuration."""
        return (self.scenario_id, self.run)

    @property
    def complete(self) -> bool:
        """Whether the episode ran to its end and was evaluated."""
        return self.status == "complete"

    @property
    def accepted(self) -> int:
        """Proposals the user accepted (directly or after gathering context)."""
        return sum(proposal.resolution == "accepted" for proposal in self.proposals)

    @property
    def simulator_fault(self) -> bool:
        """Whether the user simulator did something wrong on its own in this episode."""
        return bool(self.simulator_faults)

    @property
    def accept_reward(self) -> int:
        """The paper's per-step reward R_Accept summed over the episode: +1 per accepted proposal, -1 per
        rejected one (an expired or unanswered proposal earns 0).
        """
        rewards = {"accepted": 1, "rejected": -1}
        return sum(rewards.get(proposal.resolution, 0) for proposal in self.proposals)

    def cost_usd(self) -> float | None:
        """Cost of every model call of the episode; ``None`` when any is unknown."""
        total = RoleUsage()
        for usage in self.usage.values():
            total = total + usage
        return total.cost_usd


def role_of(actor: str, mode: str | None) -> str:
    """The model role behind a step: ``user``, ``observe`` or ``execute``."""
    return actor if actor == "user" else (mode or "observe")


def classify_proposals(trajectory: Trajectory) -> list[ProposalRecord]:
    """The decision and resolution of every proposal of an episode, from its steps, its log and what
    became of each proposal (a pure function of the trajectory).
    """
    made = {proposal.proposal_id: proposal for proposal in trajectory.proposals}
    entries = trajectory.entries
    steps = trajectory.steps
    records: list[ProposalRecord] = []
    for position, step in enumerate(steps):
        if not (step.actor == "assistant" and step.mode == "observe" and step.action.tool == SEND_MESSAGE):
            continue
        entry = entries.get(step.log_index) if step.ok and step.log_index is not None else None
        proposal = made.get(entry.proposal_id or "") if entry is not None else None
        if entry is None or proposal is None:
            continue
        decision: Decision = "truncated"
        answered_turn: int | None = None
        before_answer = 0
        for later in steps[position + 1 :]:
            if later.actor != "user":
                continue
            if proposal.expired_at is not None and later.turn > proposal.expired_at:
                break  # it expired after the user's step of that turn: later steps were not about it
            answer = _answer_of(trajectory, later.log_index, proposal.proposal_id)
            if answer is not None:
                if decision == "truncated":  # the user's first step answered it
                    decision = answer
                answered_turn = later.turn
                break
            decision = "gather_context"
            before_answer += 1
        resolution: Resolution = "truncated" if proposal.status == "pending" else proposal.status
        records.append(
            ProposalRecord(
                proposal_id=proposal.proposal_id,
                turn=step.turn,
                content=str(entry.args.get("content", "")),
                decision=decision,
                resolution=resolution,
                answered_turn=answered_turn,
                user_steps_before_answer=before_answer,
            )
        )
    return records


def _answer_of(trajectory: Trajectory, log_index: int | None, proposal_id: str) -> Decision | None:
    """``accept`` / ``reject`` when the user step at ``log_index`` answered ``proposal_id``."""
    entry = trajectory.entries.get(log_index) if log_index is not None else None
    if entry is None or entry.app != "agent_ui" or entry.tool not in ANSWERS or not entry.ok:
        return None
    return ANSWERS[entry.tool] if entry.proposal_id == proposal_id else None


def wrong_irreversible_calls(side_effects: Iterable[SideEffectRecord]) -> int | None:
    """The calls that made the irreversible ones among an episode's side effects, each counted once
    (an email to two people no solution writes to is one wrong call, two side effects); ``None`` when a
    side effect does not say which call made it (trajectories written before it was kept).
    """
    effects = list(side_effects)
    if any(change.order is None for change in effects):
        return None
    return len({change.order for change in effects if change.harm == IRREVERSIBLE})


def irreversible_calls(trajectory: Trajectory) -> int:
    """The assistant's successful calls of irreversible tools: what it did that cannot be undone, wrong or
    right (a failed call changed nothing; the user's screen actions are named per screen, not classed).
    """
    return sum(
        entry.actor == "assistant" and entry.ok and tool_harm(entry.app, entry.tool) == IRREVERSIBLE
        for entry in trajectory.log
    )


def summarize(trajectory: Trajectory, *, usage: Mapping[str, RoleUsage] | None = None) -> dict[str, Any]:
    """The fields of an :class:`EpisodeRecord` that come from a finished episode's trajectory (a pure
    function of it); ``usage`` is the model usage per role (from the episode's ledger; none for actors
    without models).
    """
    assistant_calls = [entry for entry in trajectory.log if entry.actor == "assistant"]
    failed: dict[str, int] = {}
    format_errors: dict[str, int] = {}
    for step in trajectory.steps:
        role = role_of(step.actor, step.mode)
        if not step.ok:
            failed[role] = failed.get(role, 0) + 1
        errors = len(step.action.usage.format_errors) if step.action.usage is not None else 0
        if errors:
            format_errors[role] = format_errors.get(role, 0) + errors
    outcome = trajectory.outcome
    return {
        "success": outcome.success,
        "goals": {goal.id: goal.passed for goal in outcome.goals},
        "goal_rate": outcome.goal_rate,
        "user_did_work": outcome.user_did_work,
        "side_effects": len(outcome.side_effects) + len(outcome.invented),
        "invented_details": len(outcome.invented),
        "simulator_faults": list(trajectory.simulator_faults),
        "irreversible_actions": irreversible_calls(trajectory),
        "wrong_irreversible_actions": wrong_irreversible_calls(outcome.side_effects),
        "turns": trajectory.turns,
        "ended": trajectory.ended,
        "observe_turns": len(
            {step.turn for step in trajectory.steps if step.actor == "assistant" and step.mode == "observe"}
        ),
        "proposals": classify_proposals(trajectory),
        "read_actions": sum(entry.kind == "read" for entry in assistant_calls),
        "observe_read_actions": sum(
            entry.kind == "read" and entry.mode == "observe" for entry in assistant_calls
        ),
        "write_actions": sum(entry.kind == "write" for entry in assistant_calls),
        "user_actions": sum(step.actor == "user" for step in trajectory.steps),
        "failed_steps": dict(sorted(failed.items())),
        "format_errors": dict(sorted(format_errors.items())),
        "usage": dict(sorted((usage or {}).items())),
    }
