"""One episode as its page shows it, built from the trajectory file and the episode's record.

Turns hold, in order, what the world did (scheduled events and noise as they arrived), the user's steps
with the phone as the user saw it, and the assistant's steps: observe-mode steps one by one, execute-mode
steps grouped under the task they carried out. Proposals carry the record's decision and resolution;
every check carries the log entries it names or that made the state it looked at.

The trajectory comes typed from :func:`pare.results.trajectory.read_trajectory` (older formats
upgraded there). Trajectories written before the user's view was recorded still open: the phone then
shows the app and screen from the action log and says the rest was not recorded.
"""

from __future__ import annotations

import json
import re
from dataclasses import dataclass, field
from typing import Any

from pare.agents.models.ledger import StepUsage
from pare.agents.policy import SEND_MESSAGE
from pare.env.views import split_observation
from pare.results.records import ProposalRecord
from pare.results.trajectory import ANSWERS, CheckRecord, GoalRecord, LogRecord, StepRecord, Trajectory
from pare.scenarios.checks import JUDGE_SAID
from pare.viewer._credit import Credit, Credits, pointer_parts

_THOUGHT = re.compile(r"Thought:\s*(.*?)\s*(?:\n\s*Action\s*:|$)", re.S)
_LOG_REFERENCE = re.compile(r"#(\d+)\b")
_TOOL_REFERENCE = re.compile(r"\b([a-z][a-z0-9_]*)__([a-z][a-z0-9_]*)\b")


Usage = StepUsage
"""Model usage behind one step, or summed over a role's steps."""


@dataclass
class Phone:
    """The phone as the user saw it before a step."""

    time: str
    app: str | None
    screen: str | None
    shown: Any = None
    """What the screen displayed (``None``: nothing beyond its label, or not known)."""
    notifications: list[str] = field(default_factory=list)
    pending_proposal: str | None = None
    background_apps: list[str] = field(default_factory=list)
    actions: list[str] = field(default_factory=list)
    recorded: bool = True
    """False for trajectories from before the view was recorded."""


@dataclass
class StepView:
    """One step of the user or the assistant."""

    number: int
    turn: int
    actor: str
    mode: str | None
    tool: str
    args: dict[str, Any]
    ok: bool
    observation: str
    error: str | None
    thought: str | None
    raw: str | None
    log_index: int | None
    usage: Usage | None
    phone: Phone | None = None
    proposal: ProposalRecord | None = None
    """The proposal this step made (assistant) or answered (user)."""
    answer: str | None = None
    """``accept`` or ``reject`` when this user step answered a proposal."""
    reasoning: str | None = None
    """A thinking model's reasoning behind the answer (kept apart from ``raw``)."""

    @property
    def is_report(self) -> bool:
        """An execute-mode message to the user: the task's report."""
        return self.mode == "execute" and self.tool == SEND_MESSAGE

    @property
    def args_text(self) -> str:
        """The arguments as indented JSON."""
        return json.dumps(self.args, indent=1, ensure_ascii=False) if self.args else ""


@dataclass
class ExecuteGroup:
    """The execute-mode steps that carried out one accepted task."""

    proposal: ProposalRecord | None
    steps: list[StepView]


@dataclass
class Turn:
    """One turn: the world, the user, then the assistant."""

    number: int
    time: str
    world: list[LogRecord]
    user: list[StepView]
    assistant: list[StepView | ExecuteGroup]
    after_last: bool = False
    """The world's replies delivered after the last turn, before the checks (no actor acts in it)."""


@dataclass
class CheckView:
    """One check's verdict, with the log entries behind it."""

    index: int
    form: str
    passed: bool
    description: str
    detail: str
    user_made: bool
    evidence: list[int]
    judge_said: list[str] = field(default_factory=list)
    """A judge check's reasons, from the judge model (cut from the end of its detail)."""


@dataclass
class GoalView:
    """One goal and its checks."""

    id: str
    description: str
    passed: bool
    checks: list[CheckView]


@dataclass
class Change:
    """One operation of the state diff from start to end."""

    app: str
    op: str
    path: str
    value: str | None
    credits: list[Credit]
    """Who made it, in the order they did (:mod:`pare.viewer._credit`); empty when unknown."""


@dataclass
class EpisodeView:
    """Everything the episode page shows."""

    scenario_id: str
    run: int
    label: str
    user: str
    assistant: str
    turns_played: int
    ended: str
    success: bool
    goal_rate: float
    seed: int | None
    goals: list[GoalView]
    turns: list[Turn]
    changes: list[Change] | None
    """``None`` for trajectories from before the diff was recorded."""
    log: list[LogRecord]
    proposals: list[ProposalRecord]
    usage: dict[str, Usage]
    """Summed per role (user, observe, execute) and under ``total``."""
    side_effects: list[str] = field(default_factory=list)
    """The assistant's changes that no solution of the scenario makes and the details it invented (led by
    ``invented:``), as sentences."""


def thought_of(raw: str | None) -> str | None:
    """The ``Thought:`` part of a model's answer, if any."""
    if not raw:
        return None
    found = _THOUGHT.search(raw)
    return found.group(1).strip() or None if found else None


def build_episode(
    trajectory: Trajectory,
    proposals: list[ProposalRecord],
    matched: dict[tuple[str, int], list[int]] | None = None,
) -> EpisodeView:
    """The page's view of one trajectory; ``proposals`` come from the episode's record, ``matched``
    holds the log entries each check's pattern matches when the scenario is at hand
    (:func:`pare.viewer._evidence.matched_entries`).
    """
    entries = trajectory.entries
    by_id = {proposal.proposal_id: proposal for proposal in proposals}
    steps = _steps(trajectory, by_id)
    outcome = trajectory.outcome
    credits = Credits(trajectory.log, trajectory.marks)
    goals = [_goal(goal, entries, credits, matched or {}) for goal in outcome.goals]
    usage: dict[str, Usage] = {}
    for step in steps:
        if step.usage is not None:
            role = step.mode or step.actor
            usage[role] = _add(usage.get(role), step.usage)
    ordered: dict[str, Usage] = {
        role: usage[role] for role in ("user", "observe", "execute") if role in usage
    }
    total: Usage | None = None
    for each in ordered.values():
        total = _add(total, each)
    if total is not None:
        ordered["total"] = total
    after = trajectory.after_last_turn
    diff = trajectory.state_diff
    return EpisodeView(
        scenario_id=trajectory.scenario_id,
        run=trajectory.run,
        label=trajectory.label,
        user=trajectory.user,
        assistant=trajectory.assistant,
        turns_played=trajectory.turns,
        ended=trajectory.ended,
        success=outcome.success,
        goal_rate=outcome.goal_rate,
        seed=trajectory.seed,
        goals=goals,
        turns=_turns(steps, trajectory.log, proposals, None if after is None else after.turn),
        changes=None if diff is None else _changes(diff, credits),
        log=trajectory.log,
        proposals=proposals,
        usage=ordered,
        side_effects=[
            *(change.text for change in outcome.side_effects),
            *(f"invented: {detail.text}" for detail in outcome.invented),
        ],
    )


def _add(total: Usage | None, usage: Usage) -> Usage:
    """A role's sum (without the format errors, which each step shows on its own)."""
    usage = usage.model_copy(update={"format_errors": ()})
    return usage if total is None else total + usage


def _steps(trajectory: Trajectory, proposals: dict[str, ProposalRecord]) -> list[StepView]:
    views: list[StepView] = []
    screen = _Screen()
    entries = trajectory.entries
    for number, step in enumerate(trajectory.steps):
        action = step.action
        entry = entries.get(step.log_index) if step.log_index is not None else None
        proposal_id = entry.proposal_id if entry is not None else None
        view = StepView(
            number=number,
            turn=step.turn,
            actor=step.actor,
            mode=step.mode,
            tool=action.tool,
            args=action.args,
            ok=step.ok,
            observation=step.observation,
            error=action.error,
            thought=thought_of(action.raw),
            raw=action.raw,
            log_index=entry.index if entry is not None else None,
            usage=action.usage if action.usage is not None and action.usage.calls else None,
            proposal=proposals.get(proposal_id) if proposal_id is not None else None,
            reasoning=action.reasoning,
        )
        if view.actor == "user":
            view.phone = screen.before(step, entry)
            view.answer = ANSWERS.get(view.tool) if view.ok and view.proposal is not None else None
        elif not (view.mode == "observe" and view.tool == SEND_MESSAGE):
            view.proposal = None
        views.append(view)
    return views


@dataclass
class _Screen:
    """Follows what the user's screen displays from step to step: what a step revealed (the screen it
    arrived on, the item it opened, the results it listed) stays on view until the user moves on.
    """

    shown: Any = None
    fresh: bool = False
    """``shown`` was revealed by the step just before."""
    where: str | None = None

    def before(self, step: StepRecord, entry: LogRecord | None) -> Phone:
        """The phone before ``step``; then takes in what the step revealed."""
        view = step.view
        if view is not None:
            here = f"{view.app} > {view.screen}"
            phone = Phone(
                time=view.time,
                app=view.app,
                screen=view.screen,
                notifications=view.notifications,
                pending_proposal=view.pending_proposal,
                background_apps=view.background_apps,
                actions=view.tools,
            )
            update = view.screen_update
        else:  # an older trajectory: the log knows the screen the call was made on
            here = (entry.screen or "") if entry is not None else ""
            app, _, label = here.partition(" > ")
            time = entry.time.isoformat() if entry is not None else ""
            phone = Phone(time=time, app=app or None, screen=label or None, recorded=False)
            update = None
        if update is not None:
            phone.shown = update
        elif self.fresh or here == self.where:
            phone.shown = self.shown
        revealed = _revealed(step, entry)
        self.shown, self.fresh, self.where = (
            (revealed, True, here) if revealed is not None else (phone.shown, False, here)
        )
        return phone


def _revealed(step: StepRecord, entry: LogRecord | None) -> Any:
    """What a user step put on the screen: the screen it arrived on, or an app's structured answer."""
    _, arrived = split_observation(step.observation)
    if arrived is not None:
        return arrived
    if not step.ok or entry is None or entry.app in ("system", "agent_ui"):
        return None
    return entry.result if isinstance(entry.result, dict | list) else None


def _turns(
    steps: list[StepView],
    log: list[LogRecord],
    proposals: list[ProposalRecord],
    after_last: int | None = None,
) -> list[Turn]:
    numbers = sorted({step.turn for step in steps} | {entry.turn for entry in log if entry.turn})
    turns: dict[int, Turn] = {}
    for number in numbers:
        world = [entry for entry in log if entry.turn == number and entry.actor == "env"]
        times = [entry.time.isoformat() for entry in log if entry.turn == number]
        turns[number] = Turn(number, times[0] if times else "", world, [], [], number == after_last)
    for step in steps:
        turn = turns[step.turn]
        if step.actor == "user":
            turn.user.append(step)
        elif step.mode == "execute":
            last = turn.assistant[-1] if turn.assistant else None
            if not isinstance(last, ExecuteGroup):
                task = next(
                    (p for p in proposals if p.resolution == "accepted" and p.answered_turn == step.turn),
                    None,
                )
                last = ExecuteGroup(task, [])
                turn.assistant.append(last)
            last.steps.append(step)
        else:
            turn.assistant.append(step)
    return [turns[number] for number in numbers]


def _goal(
    goal: GoalRecord,
    log: dict[int, LogRecord],
    credits: Credits,
    matched: dict[tuple[str, int], list[int]],
) -> GoalView:
    checks = []
    for check in goal.checks:
        detail, *said = check.detail.split(JUDGE_SAID)
        key = (goal.id, check.index)
        checks.append(
            CheckView(
                index=check.index,
                form=check.form,
                passed=check.passed,
                description=check.description,
                detail=detail,
                user_made=check.user_made,
                evidence=matched[key] if key in matched else evidence(check, log, credits),
                judge_said=said,
            )
        )
    return GoalView(goal.id, goal.description, goal.passed, checks)


def evidence(check: CheckRecord, log: dict[int, LogRecord], credits: Credits) -> list[int]:
    """The log entries behind a check's verdict: those its detail names (``#12``: an action check's
    calls, the texts a judge check read); for a state check, the calls that made anything at the path
    it looked at (without the scenario, which items it found is not known: see
    :func:`pare.viewer._evidence.state_entries`); otherwise the calls of the tools its detail names.
    ``log`` is the log by entry index.
    """
    detail = check.detail
    found = {int(number) for number in _LOG_REFERENCE.findall(detail)}
    if check.form == "state":
        path = re.split(r"[:\s]", detail, maxsplit=1)[0]
        found.update(credits.marked_under(path))
    elif not found:
        for app, tool in _TOOL_REFERENCE.findall(detail):
            found.update(i for i, e in log.items() if e.app == app and e.tool == tool)
    return sorted(index for index in found if index in log)


def _changes(diff: list[dict[str, Any]], credits: Credits) -> list[Change]:
    changes = []
    for op in diff:
        parts = pointer_parts(str(op.get("path", "")))
        value = op.get("value")
        changes.append(
            Change(
                app=parts[0] if parts else "",
                op=str(op.get("op", "")),
                path="/".join(parts[1:]),
                value=None if "value" not in op else json.dumps(value, indent=1, ensure_ascii=False),
                credits=credits.of(op),
            )
        )
    return changes
