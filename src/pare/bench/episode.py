"""One episode: the turn loop that alternates the user and the assistant over a scenario.

Each turn: events due by now are delivered, the user acts (``user_steps`` actions), then the assistant
acts: in observe mode up to ``observe_steps`` actions, ending at ``wait`` or a proposal; while a proposal
waits for an answer it holds back (the proposal expires after ``proposal_ttl_turns`` turns, unless that is
``None``, the paper's protocol, where it waits to the end); once the user
accepts, execute mode runs up to ``execute_steps`` actions, ending with a report. Then simulated time
moves on (:meth:`_Episode._next_time`): by ``turn_duration``, or straight to the next scheduled event when
the assistant has nothing in hand (it waited, no proposal pending) and the user either waited too or has
kept using the phone for ``attention_turns`` turns since anything last arrived: the world's timeline does
not wait on how much a user idles. No noise arrives across a jump (distractors come while someone is
active). The episode ends after ``max_turns`` turns, or earlier when nothing can happen any more (no event
to come, no proposal pending, both actors waiting), or, for a scenario marked ``end_when_met``, when both
actors wait with every goal met.

After the last turn the world's replies already set in motion (a reply due 20 minutes after the
assistant's email) are delivered, up to ``reaction_horizon`` after the end, with no actor acting any more
(:class:`AfterLastTurn`); then the final state is taken and the checks run.
"""

from __future__ import annotations

import asyncio
from dataclasses import dataclass, field, replace
from datetime import datetime, timedelta
from typing import Any, Literal

from pydantic import Field

from pare.agents.policy import (
    ASSISTANT_WAIT,
    SEND_MESSAGE,
    WAIT,
    Action,
    AssistantPolicy,
    Ending,
    EndReason,
    Task,
    TurnBudget,
    UserPolicy,
)
from pare.bench.grading import grade
from pare.bench.state_diff import state_changes
from pare.env import AssistantObservation, EnvConfig, Environment, ToolResult, TurnMark, UserView
from pare.errors import ModelRequestError
from pare.results.trajectory import TRAJECTORY_FORMAT, Trajectory, attribution_records, state_hash
from pare.scenarios.build import EventReadings, build_environment
from pare.scenarios.checks import Judge, Outcome, goals_met
from pare.scenarios.invented import InventedDetail, invented_details
from pare.scenarios.model import Scenario
from pare.scenarios.side_effects import Change
from pare.sim.log import AssistantMode, LogEntry
from pare.sim.noise import NOISE_EVENT_PREFIX

StepActor = Literal["user", "assistant"]


class EpisodeSettings(TurnBudget):
    """The turn protocol (every field of :class:`~pare.sim.budget.TurnBudget`, declared there once) and
    the world's settings.
    """

    env: EnvConfig = Field(
        default_factory=EnvConfig, description="Seed, tool failures, noise, notifications."
    )


@dataclass(frozen=True, slots=True)
class Step:
    """One action of one actor and what came of it."""

    turn: int
    actor: StepActor
    mode: AssistantMode | None
    action: Action
    ok: bool
    observation: str
    log_index: int | None
    view: dict[str, Any] | None = None
    """For a user step, the phone as the user saw it before acting (:func:`view_record`)."""


def view_record(view: UserView) -> dict[str, Any]:
    """What a trajectory keeps of the user's view: the app and screen, what changed on it, the
    notifications as truncated for the user, the pending proposal (and the turns left to answer it) and
    the actions on offer, and why the clock jumped to this turn when it did.
    """
    record: dict[str, Any] = {
        "time": view.time,
        "app": view.app,
        "screen": view.screen,
        "background_apps": view.background_apps,
        "screen_update": view.screen_update,
        "notifications": view.notifications,
        "pending_proposal": view.pending_proposal,
        "tools": view.tool_names,
    }
    if view.proposal_turns_left is not None:
        record["proposal_turns_left"] = view.proposal_turns_left
    if view.turn is not None and view.turn.clock_jump is not None:
        record["clock_jump"] = view.turn.clock_jump
    return record


@dataclass(frozen=True, slots=True)
class AfterLastTurn:
    """What the world delivered after the last turn: the replies already set in motion (events whose
    log condition held, and events waiting on those), fired in time order within the reaction horizon.
    Their log entries carry the turn number ``turn`` (one past the last turn played).
    """

    turn: int
    start: datetime
    """The clock when the last turn ended."""
    until: datetime
    """The horizon: reactions due later are not delivered."""
    delivered: tuple[str, ...]
    """The event ids delivered, in the order they fired."""
    beyond: tuple[str, ...]
    """Reactions set in motion but due after the horizon: never delivered."""

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready form."""
        return {
            "turn": self.turn,
            "from": self.start.isoformat(),
            "until": self.until.isoformat(),
            "delivered": list(self.delivered),
            "beyond": list(self.beyond),
        }


@dataclass
class EpisodeResult:
    """Everything an episode produced: its steps, the action log, the final state and the verdict."""

    scenario_id: str
    user: str
    assistant: str
    turns: int
    ended: EndReason
    steps: list[Step]
    env: Environment
    outcome: Outcome
    expired_proposals: list[str] = field(default_factory=list)
    expired_at: dict[str, int] = field(default_factory=dict)
    """The turn in which each expired proposal expired (after the user's step of that turn)."""
    proposed_at: dict[str, int] = field(default_factory=dict)
    """The turn in which each proposal was made."""
    start_state_hash: str | None = None
    """The content hash of the apps' data at the start (:func:`~pare.results.trajectory.state_hash`)."""
    state_diff: list[dict[str, Any]] = field(default_factory=list)
    """The apps' data from start to end as JSON Patch operations."""
    after_last_turn: AfterLastTurn | None = None
    """The replies delivered after the last turn; ``None`` when none was set in motion."""
    changes: list[Change] = field(default_factory=list)
    """What the assistant changed in the apps' data (:func:`~pare.scenarios.side_effects.assistant_changes`);
    those no solution of the scenario makes are the outcome's side effects."""
    invented: list[InventedDetail] = field(default_factory=list)
    """The details the assistant wrote that nothing in its world gives (:mod:`pare.scenarios.invented`),
    found whether or not the verdict counts them (the gate judges a run without them, then adds them)."""
    closing: dict[str, str] = field(default_factory=dict)
    """The closing observation that ended each model-backed actor's conversation, by role (``user``,
    ``assistant``); actors without a conversation have none."""

    @property
    def success(self) -> bool:
        """Whether every goal was met."""
        return self.outcome.success

    def trajectory(
        self, *, label: str = "", run: int = 1, seed: int | None = None, scenario_hash: str = ""
    ) -> Trajectory:
        """The episode as its trajectory file keeps it (``label``, ``run``, ``seed`` and
        ``scenario_hash`` say which episode of which run it is).
        """
        env = self.env
        places, removals = attribution_records(env.attribution)
        data: dict[str, Any] = {
            "format": TRAJECTORY_FORMAT,
            "label": label,
            "run": run,
            "seed": seed,
            "scenario_hash": scenario_hash,
            "scenario_id": self.scenario_id,
            "user": self.user,
            "assistant": self.assistant,
            "turns": self.turns,
            "ended": self.ended,
            "proposals": [
                {
                    "proposal_id": proposal.proposal_id,
                    "turn": self.proposed_at.get(proposal.proposal_id, 0),
                    "content": proposal.content,
                    "status": proposal.status,
                    "expired_at": self.expired_at.get(proposal.proposal_id),
                }
                for proposal in env.agent_ui.state.proposals
            ],
            # read by attribute: no JSON-ready copy of every step and entry made only to be read again
            "steps": self.steps,
            "log": env.log.entries,
            "attribution": places,
            "removals": removals,
            "outcome": self.outcome.to_dict(),
            "state_diff": self.state_diff,
            "start_state_hash": self.start_state_hash,
            "after_last_turn": None if self.after_last_turn is None else self.after_last_turn.to_dict(),
            "closing": self.closing,
        }
        return Trajectory.model_validate(data, from_attributes=True)

    def to_dict(self) -> dict[str, Any]:
        """The trajectory's JSON form (:meth:`trajectory`, without saying which run it is)."""
        data: dict[str, Any] = self.trajectory().model_dump(mode="json", by_alias=True)
        return data


async def arun_episode(
    scenario: Scenario,
    user: UserPolicy,
    assistant: AssistantPolicy,
    settings: EpisodeSettings | None = None,
    *,
    judge: Judge | None = None,
    side_effects: bool = True,
) -> EpisodeResult:
    """Play ``scenario`` with ``user`` and ``assistant`` and evaluate its goals (in a running event loop,
    so many episodes can wait on model calls at once). ``judge`` reads the free-text checks, and the
    triggering texts of reactive events that have a ``judge``. With ``side_effects`` (the default), a change
    of the assistant's that none of the scenario's solutions makes fails the episode (see
    :mod:`pare.scenarios.side_effects`; the solutions are played once per scenario to know).
    """
    episode = _Episode(scenario, user, assistant, settings or EpisodeSettings(), judge)
    return await episode.run(judge, side_effects=side_effects)


def run_episode(
    scenario: Scenario,
    user: UserPolicy,
    assistant: AssistantPolicy,
    settings: EpisodeSettings | None = None,
    *,
    judge: Judge | None = None,
    side_effects: bool = True,
) -> EpisodeResult:
    """Play ``scenario`` with ``user`` and ``assistant`` and evaluate its goals (outside an event loop);
    ``side_effects`` as in :func:`arun_episode`.
    """
    played: list[EpisodeResult] = []

    async def play() -> None:
        # Kept in a list rather than returned: on Python 3.11, asyncio.run formats the repr of the task
        # (and so of what it returned) when it puts back the Ctrl-C handler, and a result's repr walks
        # the whole episode.
        played.append(
            await arun_episode(scenario, user, assistant, settings, judge=judge, side_effects=side_effects)
        )

    asyncio.run(play())
    return played[0]


JUMP_ALL_WAITED = "nothing was happening until the next event"
"""Why the clock jumped when the user and the assistant both waited."""
JUMP_NOTHING_NEW = "nothing new had arrived for a while, so the day moved on to the next event"
"""Why the clock jumped when the user kept using the phone with nothing new (``attention_turns``)."""


def duration_words(span: timedelta) -> str:
    """``span`` in words to the minute, e.g. ``1 hour 5 minutes`` (``less than a minute`` below one)."""
    minutes = int(span.total_seconds() // 60)
    if minutes < 1:
        return "less than a minute"
    days, rest = divmod(minutes, 24 * 60)
    hours, minutes = divmod(rest, 60)
    parts = [(days, "day"), (hours, "hour"), (minutes, "minute")]
    return " ".join(f"{count} {unit}{'s' if count != 1 else ''}" for count, unit in parts if count)


def _from_the_story(entry: LogEntry) -> bool:
    """Whether ``entry`` is the world acting on the scenario's timeline: a scheduled event or an app's
    wakeup (a reminder falling due), not a distractor.
    """
    return entry.actor == "env" and not (entry.event_id or "").startswith(NOISE_EVENT_PREFIX)


class _Episode:
    def __init__(
        self,
        scenario: Scenario,
        user: UserPolicy,
        assistant: AssistantPolicy,
        settings: EpisodeSettings,
        judge: Judge | None = None,
    ) -> None:
        self.scenario = scenario
        self.user = user
        self.assistant = assistant
        self.settings = settings
        self.readings = EventReadings(judge) if judge is not None else None
        """The judge's readings of reactive events' triggering texts: the world reads text by it too."""
        self.env = build_environment(scenario, settings.env, readings=self.readings)
        self.start_state = self.env.snapshot(shared=True)  # read only: diffed at the end
        self.steps: list[Step] = []
        self.handled: set[str] = set()
        """Proposals the assistant has already executed (or that expired)."""
        self.proposed_at: dict[str, int] = {}
        self.expired: list[str] = []
        self.expired_at: dict[str, int] = {}
        self.turn = 0
        self.last_arrival = 1
        """The last turn in which something arrived from the world (the start counts as turn 1)."""
        self.user_previous: ToolResult | None = None
        self.assistant_previous: ToolResult | None = None
        self.mark = TurnMark(0, settings.max_turns)
        """The turn under way as the actors are told it; its clock jump goes to each actor's first look."""
        self.jump_told: set[StepActor] = set()

    async def run(self, judge: Judge | None, *, side_effects: bool) -> EpisodeResult:
        env = self.env
        budget = self.settings.budget()
        self.user.start(env, budget)
        self.assistant.start(env, budget)
        try:
            ended = await self._turns()
        except ModelRequestError as error:
            if error.kind != "context_length":
                raise
            ended = "context_limit"  # the model cannot take the episode further: judge what it achieved
        closing = self._close(ended)
        # The order matters: the world's pending replies first, then the final state, then the checks.
        after = self._after_last_turn()
        final = env.snapshot(shared=True)  # read only: evaluated and diffed
        outcome, changes = await grade(
            self.scenario,
            env.log.entries,
            self.start_state,
            final,
            env.attribution,
            judge=judge,
            side_effects=side_effects,
        )
        invented = (
            list(outcome.invented)
            if side_effects
            else invented_details(self.scenario, env.log.entries, self.start_state, final)
        )
        return EpisodeResult(
            scenario_id=self.scenario.id,
            user=self.user.name,
            assistant=self.assistant.name,
            turns=self.turn,
            ended=ended,
            steps=self.steps,
            env=env,
            outcome=outcome,
            expired_proposals=self.expired,
            expired_at=self.expired_at,
            proposed_at=self.proposed_at,
            start_state_hash=state_hash(self.start_state),
            state_diff=state_changes(self.start_state, final),
            after_last_turn=after,
            changes=changes,
            invented=invented,
            closing=closing,
        )

    def _close(self, ended: EndReason) -> dict[str, str]:
        """Tell each actor the session is over, with what it had not seen yet: the result of its last
        action, the user's notifications since (the assistant's report of a task carried out in the last
        turn), the assistant's observation since it last looked. No model is called; notifications are
        not app data, so taking them changes no state the checks read.
        """
        ending = Ending(self.turn, self.settings.max_turns, ended)
        closing: dict[str, str] = {}
        user_text = self.user.finish(ending, self.user_previous, self.env.notifications.take_unread("user"))
        if user_text is not None:
            closing["user"] = user_text
        observation = replace(self.env.assistant_observation(), turn=replace(self.mark, clock_jump=None))
        assistant_text = self.assistant.finish(ending, observation, self.assistant_previous)
        if assistant_text is not None:
            closing["assistant"] = assistant_text
        return closing

    def _after_last_turn(self) -> AfterLastTurn | None:
        """Deliver the replies already set in motion and due within the horizon, as a phase of its own
        (its log entries are numbered one turn past the last); ``None`` when nothing was set in motion.
        """
        env = self.env
        if not env.scheduler.scheduled_reactions():
            return None
        start = env.clock.now
        until = start + self.settings.reaction_horizon
        turn = env.begin_turn()
        delivered = env.deliver_reactions(until)
        return AfterLastTurn(turn, start, until, tuple(delivered), tuple(env.scheduler.scheduled_reactions()))

    async def _turns(self) -> EndReason:
        """Play turns until the limit or until nothing can happen any more."""
        env = self.env
        active_until = resume_at = env.clock.now
        jump: str | None = None
        for turn in range(1, self.settings.max_turns + 1):
            self.turn = turn
            env.begin_turn()
            before = len(env.log)
            last_turn_began = env.clock.now
            # time passes at the start of the turn, so what it brings is logged under the turn that sees it;
            # noise arrives only while someone was active, the rest of a jump is quiet
            env.advance_to(active_until)
            env.advance_to(resume_at, quiet=True)
            self._mark_turn(turn, env.clock.now - last_turn_began, jump)
            if any(_from_the_story(entry) for entry in env.log.since(before)):
                self.last_arrival = turn
            user_waited = await self._user_turn(turn)
            self._expire_stale(turn)
            assistant_waited = await self._assistant_turn(turn)
            everyone_waited = user_waited and assistant_waited and env.agent_ui.pending is None
            if everyone_waited and (env.next_event_time() is None or self._settled()):
                return "idle"
            active_until, resume_at, jump = self._next_time(turn, user_waited, assistant_waited)
        return "max_turns"

    def _mark_turn(self, turn: int, moved: timedelta, jump: str | None) -> None:
        """What the actors are told of this turn: its number and, when the clock moved further than a
        turn takes, by how much and why (``jump``, from :meth:`_next_time`).
        """
        told = None
        if turn > 1 and jump is not None and moved > self.settings.turn_duration:
            told = f"the clock jumped {duration_words(moved)}: {jump}"
        self.mark = TurnMark(turn, self.settings.max_turns, told)
        self.jump_told = set()

    def _turn_mark(self, actor: StepActor) -> TurnMark:
        """The turn's mark for ``actor``'s next look: the clock jump is told once, at the first."""
        if actor in self.jump_told:
            return replace(self.mark, clock_jump=None)
        self.jump_told.add(actor)
        return self.mark

    def _next_time(
        self, turn: int, user_waited: bool, assistant_waited: bool
    ) -> tuple[datetime, datetime, str | None]:
        """Where the clock goes before the next turn: (until when distractors may arrive, when it starts,
        why it jumps past a turn's duration, or ``None`` when it does not).

        Someone acted: ``turn_duration`` later. The assistant has nothing in hand (it waited, no proposal
        pending) and the user waited too: straight to the next scheduled event, quietly. The assistant has
        nothing in hand and the user kept using the phone for ``attention_turns`` turns since anything
        last arrived: the user's turn takes its ``turn_duration``, then the clock goes on to the next
        scheduled event; so a user who never waits still sees the scenario's whole timeline, and one who
        is reading what just arrived is not hurried past it.
        """
        env = self.env
        now = env.clock.now
        active = now + self.settings.turn_duration
        upcoming = env.next_event_time()
        if upcoming is None or not assistant_waited or env.agent_ui.pending is not None:
            return active, active, None
        if user_waited:
            return now, max(upcoming, now), JUMP_ALL_WAITED
        if turn - self.last_arrival + 1 > self.settings.attention_turns:
            return active, max(upcoming, active), JUMP_NOTHING_NEW
        return active, active, None

    def _settled(self) -> bool:
        """For a scenario that ends when met: every goal is met now, so what is still to come cannot
        change the verdict (judge checks are read with their deterministic fallbacks here). The state
        is snapshot only if the checks on the action log all hold and a state check is reached.
        """
        if not self.scenario.end_when_met:
            return False
        env = self.env
        return goals_met(self.scenario, env.log.entries, env.shared_snapshot, attribution=env.attribution)

    # -- the user --------------------------------------------------------------------------------------
    async def _user_turn(self, turn: int) -> bool:
        """The user's steps; True when the user only waited."""
        waited = True
        for _ in range(self.settings.user_steps):
            view = replace(
                self.env.user_view(), turn=self._turn_mark("user"), proposal_turns_left=self._turns_left(turn)
            )
            action = await self.user.step(view, self.user_previous)
            result = await self._perform("user", action, None)
            self._record(turn, "user", None, action, result, view_record(view))
            self.user_previous = result
            if action.tool == WAIT:
                break
            waited = False
        return waited

    def _turns_left(self, turn: int) -> int | None:
        """Turns the pending proposal may still be answered in, this one included (``None``: none pending).

        A proposal made in turn ``t`` can be answered in turns ``t + 1`` to ``t + proposal_ttl_turns``;
        unanswered by the end of the user's part of the last, it is withdrawn (:meth:`_expire_stale`).
        """
        pending = self.env.agent_ui.pending
        lifetime = self.settings.proposal_ttl_turns
        if pending is None or lifetime is None:
            return None
        asked = self.proposed_at.get(pending.proposal_id, turn)
        return max(1, lifetime - (turn - asked) + 1)

    def _expire_stale(self, turn: int) -> None:
        pending = self.env.agent_ui.pending
        if pending is None:
            return
        asked = self.proposed_at.setdefault(pending.proposal_id, turn)
        lifetime = self.settings.proposal_ttl_turns
        if lifetime is not None and turn - asked >= lifetime:
            self.env.agent_ui.expire_pending()
            self.handled.add(pending.proposal_id)
            self.expired.append(pending.proposal_id)
            self.expired_at[pending.proposal_id] = turn

    # -- the assistant ---------------------------------------------------------------------------------
    async def _assistant_turn(self, turn: int) -> bool:
        """The assistant's steps this turn; True when it only waited (or awaits an answer)."""
        accepted = self._accepted_task()
        if accepted is not None:
            await self._execute(turn, accepted)
            self.assistant_previous = None  # the observe conversation did not make the execute calls
            return False
        if self.env.agent_ui.pending is not None:
            return True  # awaiting confirmation
        return await self._observe(turn)

    def _accepted_task(self) -> Task | None:
        for proposal in self.env.agent_ui.state.proposals:
            if proposal.status == "accepted" and proposal.proposal_id not in self.handled:
                self.handled.add(proposal.proposal_id)
                return Task(proposal.content, proposal.reason, proposal.proposal_id)
        return None

    async def _observe(self, turn: int) -> bool:
        observation: AssistantObservation = replace(
            self.env.assistant_observation(), turn=self._turn_mark("assistant")
        )
        previous = self.assistant_previous  # the result of its last action, which ended its last turn
        for step in range(self.settings.observe_steps):
            action = await self.assistant.observe(observation if step == 0 else None, previous)
            previous = await self._perform("assistant", action, "observe")
            self.assistant_previous = previous
            self._record(turn, "assistant", "observe", action, previous)
            if action.tool == ASSISTANT_WAIT:
                return step == 0
            if action.tool == SEND_MESSAGE and previous.ok:
                pending = self.env.agent_ui.pending
                if pending is not None:
                    self.proposed_at[pending.proposal_id] = turn
                return False
        return False

    async def _execute(self, turn: int, task: Task) -> None:
        previous: ToolResult | None = None
        for step in range(self.settings.execute_steps):
            action = await self.assistant.execute(task if step == 0 else None, previous)
            previous = await self._perform("assistant", action, "execute")
            self._record(turn, "assistant", "execute", action, previous)
            if action.tool == SEND_MESSAGE and previous.ok:
                return

    async def _perform(self, actor: StepActor, action: Action, mode: AssistantMode | None) -> ToolResult:
        """Hand a valid action to the environment; an actor's failure to produce one is its own result.
        A reactive event that waits for the judge's reading of what the action wrote gets it before anything
        else happens (:class:`~pare.scenarios.build.EventReadings`).
        """
        if action.error is not None:
            return ToolResult(ok=False, error=action.error)
        if actor == "user":
            result = self.env.call("user", action.tool, action.args)
        else:
            result = self.env.call("assistant", action.tool, action.args, mode=mode)
        scheduler = self.env.scheduler
        while scheduler.undecided and self.readings is not None:
            await self.readings.ask()
            scheduler.retest()
        return result

    def _record(
        self,
        turn: int,
        actor: StepActor,
        mode: AssistantMode | None,
        action: Action,
        result: ToolResult,
        view: dict[str, Any] | None = None,
    ) -> None:
        index = result.entry.index if result.entry is not None else None
        self.steps.append(Step(turn, actor, mode, action, result.ok, result.observation(), index, view))
