"""One line per episode in a run's store: what the metrics need, derived once from the trajectory.

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

from collections.abc import Mapping
from typing import TYPE_CHECKING, Any, Literal

from pydantic import BaseModel, ConfigDict, Field, field_validator

from pare.agents.models.ledger import RoleUsage
from pare.agents.policy import SEND_MESSAGE

if TYPE_CHECKING:
    from pare.bench.episode import EpisodeResult

RECORD_FORMAT = 1

Decision = Literal["accept", "reject", "gather_context", "truncated"]
Resolution = Literal["accepted", "rejected", "expired", "truncated"]
EpisodeStatus = Literal["complete", "failed"]
FailureKind = Literal["provider_unavailable", "cache_miss", "internal_error"]
FaultKind = Literal["accepted_wrong", "rejected_right", "did_by_hand", "stalled", "unseen_fact"]
"""What the user simulator did wrong on its own (see :mod:`pare.bench.simulator_faults` for each rule)."""

DECISIONS: tuple[Decision, ...] = ("accept", "reject", "gather_context", "truncated")
RESOLUTIONS: tuple[Resolution, ...] = ("accepted", "rejected", "expired", "truncated")
FAULT_KINDS: tuple[FaultKind, ...] = (
    "accepted_wrong",
    "rejected_right",
    "did_by_hand",
    "stalled",
    "unseen_fact",
)
ANSWERS: dict[str, Decision] = {"accept_proposal": "accept", "reject_proposal": "reject"}


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


class SimulatorFault(BaseModel):
    """Something the user simulator did wrong independently of the assistant, found when the episode ended."""

    model_config = ConfigDict(extra="forbid", frozen=True, allow_inf_nan=False)

    kind: FaultKind
    turn: int = Field(description="The turn of the user's step at fault (or of the proposal it left).")
    detail: str = Field(description="What happened, in one sentence.")
    proposal_id: str | None = Field(default=None, description="The proposal concerned, if any.")


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
        description="Changes the assistant made that no solution of the scenario makes (any fails the "
        "episode; the trajectory's outcome names them).",
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


def classify_proposals(result: EpisodeResult) -> list[ProposalRecord]:
    """The decision and resolution of every proposal of an episode, from its steps and final state."""
    log = result.env.log
    final = {p.proposal_id: p for p in result.env.agent_ui.state.proposals}
    records: list[ProposalRecord] = []
    for position, step in enumerate(result.steps):
        if not (step.actor == "assistant" and step.mode == "observe" and step.action.tool == SEND_MESSAGE):
            continue
        if not step.ok or step.log_index is None:
            continue
        entry = log[step.log_index]
        proposal_id = entry.result.get("proposal_id") if isinstance(entry.result, dict) else None
        if proposal_id is None or proposal_id not in final:
            continue
        decision: Decision = "truncated"
        answered_turn: int | None = None
        before_answer = 0
        expired_turn = result.expired_at.get(proposal_id)
        for later in result.steps[position + 1 :]:
            if later.actor != "user":
                continue
            if expired_turn is not None and later.turn > expired_turn:
                break  # it expired after the user's step of that turn: later steps were not about it
            answer = _answer_of(result, later.log_index, proposal_id)
            if answer is not None:
                if decision == "truncated":  # the user's first step answered it
                    decision = answer
                answered_turn = later.turn
                break
            decision = "gather_context"
            before_answer += 1
        status = final[proposal_id].status
        resolution: Resolution = "truncated" if status == "pending" else status
        records.append(
            ProposalRecord(
                proposal_id=proposal_id,
                turn=step.turn,
                content=str(entry.args.get("content", "")),
                decision=decision,
                resolution=resolution,
                answered_turn=answered_turn,
                user_steps_before_answer=before_answer,
            )
        )
    return records


def _answer_of(result: EpisodeResult, log_index: int | None, proposal_id: str) -> Decision | None:
    """``accept`` / ``reject`` when the user step at ``log_index`` answered ``proposal_id``."""
    if log_index is None:
        return None
    entry = result.env.log[log_index]
    if entry.app != "agent_ui" or entry.tool not in ANSWERS or not entry.ok:
        return None
    answered = entry.result.get("proposal_id") if isinstance(entry.result, dict) else None
    return ANSWERS[entry.tool] if answered == proposal_id else None


def summarize(result: EpisodeResult, *, usage: Mapping[str, RoleUsage] | None = None) -> dict[str, Any]:
    """The fields of an :class:`EpisodeRecord` that come from a finished episode; ``usage`` is the model
    usage per role (from the episode's ledger; none for actors without models).
    """
    assistant_calls = [entry for entry in result.env.log if entry.actor == "assistant"]
    failed: dict[str, int] = {}
    format_errors: dict[str, int] = {}
    for step in result.steps:
        role = role_of(step.actor, step.mode)
        if not step.ok:
            failed[role] = failed.get(role, 0) + 1
        errors = len((step.action.usage or {}).get("format_errors", []))
        if errors:
            format_errors[role] = format_errors.get(role, 0) + errors
    return {
        "success": result.outcome.success,
        "goals": {goal.id: goal.passed for goal in result.outcome.goals},
        "goal_rate": result.outcome.goal_rate,
        "user_did_work": result.outcome.user_did_work,
        "side_effects": len(result.outcome.side_effects),
        "turns": result.turns,
        "ended": result.ended,
        "observe_turns": len(
            {step.turn for step in result.steps if step.actor == "assistant" and step.mode == "observe"}
        ),
        "proposals": classify_proposals(result),
        "read_actions": sum(entry.kind == "read" for entry in assistant_calls),
        "observe_read_actions": sum(
            entry.kind == "read" and entry.mode == "observe" for entry in assistant_calls
        ),
        "write_actions": sum(entry.kind == "write" for entry in assistant_calls),
        "user_actions": sum(step.actor == "user" for step in result.steps),
        "failed_steps": dict(sorted(failed.items())),
        "format_errors": dict(sorted(format_errors.items())),
        "usage": dict(sorted((usage or {}).items())),
    }
