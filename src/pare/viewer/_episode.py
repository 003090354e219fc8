"""One episode as its page shows it, built from the trajectory file and the episode's record.

Turns hold, in order, what the world did (scheduled events and noise as they arrived), the user's steps
with the phone as the user saw it, and the assistant's steps: observe-mode steps one by one, execute-mode
steps grouped under the task they carried out. Proposals carry the record's decision and resolution;
every check carries the log entries it names or that made the state it looked at.

Trajectories written before the user's view was recorded still open: the phone then shows the app and
screen from the action log and says the rest was not recorded.
"""

from __future__ import annotations

import json
import re
from dataclasses import dataclass, field
from typing import Any

from pare.results.records import ProposalRecord
from pare.scenarios.checks import JUDGE_SAID
from pare.viewer._credit import Credit, Credits, pointer_parts

SEND_MESSAGE = "agent_ui__send_message_to_user"
ANSWERS = {"accept_proposal": "accept", "reject_proposal": "reject"}
ON_SCREEN = "\nOn screen: "
_THOUGHT = re.compile(r"Thought:\s*(.*?)\s*(?:\n\s*Action\s*:|$)", re.S)
_LOG_REFERENCE = re.compile(r"#(\d+)\b")
_TOOL_REFERENCE = re.compile(r"\b([a-z][a-z0-9_]*)__([a-z][a-z0-9_]*)\b")


@dataclass
class Usage:
    """Model usage behind one step (none for deterministic actors)."""

    calls: int = 0
    prompt_tokens: int = 0
    completion_tokens: int = 0
    cost_usd: float | None = 0.0
    format_errors: list[str] = field(default_factory=list)

    @property
    def tokens(self) -> int:
        """Prompt plus completion tokens."""
        return self.prompt_tokens + self.completion_tokens

    @property
    def cost_text(self) -> str:
        """The cost in words ("unknown" when any call had no price)."""
        return "unknown" if self.cost_usd is None else f"${self.cost_usd:.4f}"

    @classmethod
    def of(cls, data: Any) -> Usage | None:
        """Read a step's ``action.usage``; ``None`` when it has none."""
        if not isinstance(data, dict) or not data.get("calls"):
            return None
        cost = data.get("cost_usd")
        errors = data.get("format_errors")
        return cls(
            calls=int(data.get("calls", 0)),
            prompt_tokens=int(data.get("prompt_tokens", 0)),
            completion_tokens=int(data.get("completion_tokens", 0)),
            cost_usd=float(cost) if isinstance(cost, int | float) else None,
            format_errors=[str(e) for e in errors] if isinstance(errors, list) else [],
        )


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
    world: list[dict[str, Any]]
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
    log: list[dict[str, Any]]
    proposals: list[ProposalRecord]
    usage: dict[str, Usage]
    """Summed per role (user, observe, execute) and under ``total``."""
    side_effects: list[str] = field(default_factory=list)
    """The assistant's changes that no solution of the scenario makes, as sentences."""


def thought_of(raw: str | None) -> str | None:
    """The ``Thought:`` part of a model's answer, if any."""
    if not raw:
        return None
    found = _THOUGHT.search(raw)
    return found.group(1).strip() or None if found else None


def split_observation(text: str) -> tuple[str, Any]:
    """A user step's observation as (result text, what the screen arrived on displays or ``None``)."""
    head, marker, tail = text.partition(ON_SCREEN)
    if not marker:
        return text, None
    try:
        return head, json.loads(tail)
    except json.JSONDecodeError:
        return head, tail


def episode_log(data: dict[str, Any]) -> list[dict[str, Any]]:
    """The trajectory's action log (its well-formed entries)."""
    return [
        entry
        for entry in data.get("log", [])
        if isinstance(entry, dict) and isinstance(entry.get("index"), int)
    ]


def by_index(log: list[dict[str, Any]]) -> dict[int, dict[str, Any]]:
    """The log's entries by their own index, which the steps, checks and attribution name (an entry's
    position in the list is not its index once a malformed entry was left out).
    """
    return {int(entry["index"]): entry for entry in log}


def build_episode(
    data: dict[str, Any],
    proposals: list[ProposalRecord],
    matched: dict[tuple[str, int], list[int]] | None = None,
) -> EpisodeView:
    """The page's view of one trajectory; ``proposals`` come from the episode's record, ``matched``
    holds the log entries each check's pattern matches when the scenario is at hand
    (:func:`pare.viewer._evidence.matched_entries`).
    """
    log = episode_log(data)
    entries = by_index(log)
    by_id = {proposal.proposal_id: proposal for proposal in proposals}
    steps = _steps(data, entries, by_id)
    outcome = data.get("outcome") or {}
    attribution = data.get("attribution") or {}
    goals = [_goal(goal, entries, attribution, matched or {}) for goal in outcome.get("goals", [])]
    diff = data.get("state_diff")
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
    return EpisodeView(
        scenario_id=str(data.get("scenario_id", "")),
        run=int(data.get("run", 0)),
        label=str(data.get("label", "")),
        user=str(data.get("user", "")),
        assistant=str(data.get("assistant", "")),
        turns_played=int(data.get("turns", 0)),
        ended=str(data.get("ended", "")),
        success=bool(outcome.get("success", False)),
        goal_rate=float(outcome.get("goal_rate", 0.0)),
        seed=data.get("seed") if isinstance(data.get("seed"), int) else None,
        goals=goals,
        turns=_turns(steps, log, proposals, _after_last_turn(data)),
        changes=None if not isinstance(diff, list) else _changes(diff, Credits(log, attribution)),
        log=log,
        proposals=proposals,
        usage=ordered,
        side_effects=[
            str(change.get("text", ""))
            for change in outcome.get("side_effects") or []
            if isinstance(change, dict)
        ],
    )


def _add(total: Usage | None, usage: Usage) -> Usage:
    if total is None:
        return Usage(usage.calls, usage.prompt_tokens, usage.completion_tokens, usage.cost_usd)
    cost = None if total.cost_usd is None or usage.cost_usd is None else total.cost_usd + usage.cost_usd
    return Usage(
        total.calls + usage.calls,
        total.prompt_tokens + usage.prompt_tokens,
        total.completion_tokens + usage.completion_tokens,
        cost,
    )


def _steps(
    data: dict[str, Any], log: dict[int, dict[str, Any]], proposals: dict[str, ProposalRecord]
) -> list[StepView]:
    views: list[StepView] = []
    screen = _Screen()
    for number, step in enumerate(data.get("steps", [])):
        action = step.get("action") or {}
        index = step.get("log_index")
        entry = log.get(index) if isinstance(index, int) else None
        result = entry.get("result") if entry else None
        args = action.get("args")
        proposal_id = result.get("proposal_id") if isinstance(result, dict) else None
        view = StepView(
            number=number,
            turn=int(step.get("turn", 0)),
            actor=str(step.get("actor", "")),
            mode=step.get("mode"),
            tool=str(action.get("tool", "")),
            args=args if isinstance(args, dict) else {},
            ok=bool(step.get("ok", False)),
            observation=str(step.get("observation", "")),
            error=action.get("error"),
            thought=thought_of(action.get("raw")),
            raw=action.get("raw"),
            log_index=index if entry is not None else None,
            usage=Usage.of(action.get("usage")),
            proposal=proposals.get(proposal_id) if isinstance(proposal_id, str) else None,
            reasoning=reasoning if isinstance(reasoning := action.get("reasoning"), str) else None,
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

    def before(self, step: dict[str, Any], entry: dict[str, Any] | None) -> Phone:
        """The phone before ``step``; then takes in what the step revealed."""
        view = step.get("view")
        if isinstance(view, dict):
            here = f"{view.get('app')} > {view.get('screen')}"
            phone = Phone(
                time=str(view.get("time", "")),
                app=view.get("app"),
                screen=view.get("screen"),
                notifications=[str(n) for n in view.get("notifications") or []],
                pending_proposal=view.get("pending_proposal"),
                background_apps=[str(a) for a in view.get("background_apps") or []],
                actions=[str(a) for a in view.get("tools") or []],
            )
            update = view.get("screen_update")
        else:  # an older trajectory: the log knows the screen the call was made on
            here = str(entry.get("screen") or "") if entry else ""
            app, _, label = here.partition(" > ")
            time = str(entry.get("time", "")) if entry else ""
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


def _revealed(step: dict[str, Any], entry: dict[str, Any] | None) -> Any:
    """What a user step put on the screen: the screen it arrived on, or an app's structured answer."""
    _, arrived = split_observation(str(step.get("observation", "")))
    if arrived is not None:
        return arrived
    if not step.get("ok") or entry is None or entry.get("app") in ("system", "agent_ui"):
        return None
    result = entry.get("result")
    return result if isinstance(result, dict | list) else None


def _after_last_turn(data: dict[str, Any]) -> int | None:
    """The number the log gives the phase after the last turn, if the trajectory has one."""
    after = data.get("after_last_turn")
    turn = after.get("turn") if isinstance(after, dict) else None
    return turn if isinstance(turn, int) else None


def _turns(
    steps: list[StepView],
    log: list[dict[str, Any]],
    proposals: list[ProposalRecord],
    after_last: int | None = None,
) -> list[Turn]:
    numbers = sorted({step.turn for step in steps} | {int(e.get("turn", 0)) for e in log if e.get("turn")})
    turns: dict[int, Turn] = {}
    for number in numbers:
        world = [e for e in log if e.get("turn") == number and e.get("actor") == "env"]
        times = [str(e.get("time", "")) for e in log if e.get("turn") == number]
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
    goal: dict[str, Any],
    log: dict[int, dict[str, Any]],
    attribution: dict[str, Any],
    matched: dict[tuple[str, int], list[int]],
) -> GoalView:
    goal_id = str(goal.get("id", ""))
    checks = []
    for check in goal.get("checks", []):
        detail, *said = str(check.get("detail", "")).split(JUDGE_SAID)
        checks.append(
            CheckView(
                index=int(check.get("index", 0)),
                form=str(check.get("form", "")),
                passed=bool(check.get("passed", False)),
                description=str(check.get("description", "")),
                detail=detail,
                user_made=bool(check.get("user_made", False)),
                evidence=_evidence_of(goal_id, check, log, attribution, matched),
                judge_said=said,
            )
        )
    return GoalView(goal_id, str(goal.get("description", "")), bool(goal.get("passed")), checks)


def _evidence_of(
    goal_id: str,
    check: dict[str, Any],
    log: dict[int, dict[str, Any]],
    attribution: dict[str, Any],
    matched: dict[tuple[str, int], list[int]],
) -> list[int]:
    key = (goal_id, int(check.get("index", 0)))
    return matched[key] if key in matched else evidence(check, log, attribution)


def evidence(check: dict[str, Any], log: dict[int, dict[str, Any]], attribution: dict[str, Any]) -> list[int]:
    """The log entries behind a check's verdict: those its detail names (``#12``: an action check's
    calls, the texts a judge check read); for a state check, the calls that made anything at the path
    it looked at (without the scenario, which items it found is not known: see
    :func:`pare.viewer._evidence.state_entries`); otherwise the calls of the tools its detail names.
    ``log`` is the log by entry index.
    """
    detail = str(check.get("detail", ""))
    found = {int(number) for number in _LOG_REFERENCE.findall(detail)}
    if check.get("form") == "state":
        path = re.split(r"[:\s]", detail, maxsplit=1)[0]
        for place, mark in attribution.items():
            if (place == path or place.startswith(path + ".")) and isinstance(mark, dict):
                found.update(
                    i for i in (mark.get("created_at"), mark.get("changed_at")) if isinstance(i, int)
                )
    elif not found:
        for app, tool in _TOOL_REFERENCE.findall(detail):
            found.update(i for i, e in log.items() if e.get("app") == app and e.get("tool") == tool)
    return sorted(index for index in found if index in log)


def _changes(diff: list[Any], credits: Credits) -> list[Change]:
    changes = []
    for op in diff:
        if not isinstance(op, dict):
            continue
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
