"""The turn loop: order, modes, time, expiry, limits and determinism."""

from __future__ import annotations

import json
from datetime import timedelta

from pare.agents import (
    ASSISTANT_WAIT,
    SEND_MESSAGE,
    WAIT,
    Action,
    AssistantPolicy,
    SilentAssistant,
    Task,
    UserPolicy,
)
from pare.bench import EpisodeSettings, run_episode
from pare.env import AssistantObservation, EnvConfig, ToolResult, UserView
from pare.results.trajectory import write_trajectory
from pare.scenarios import OracleAssistant, OracleUser
from tests.scenarios.helpers import base, parse

SCENARIO = parse(base())
SCENARIO_CONFIG = EnvConfig(seed=7, noise_rate_per_minute=2.0)


class Answering(UserPolicy):
    """Waits, except that it answers a pending proposal as told (or never)."""

    def __init__(self, answer: str | None) -> None:
        self.answer = answer
        self.views: list[UserView] = []

    async def step(self, view: UserView, previous: ToolResult | None) -> Action:
        self.views.append(view)
        if view.pending_proposal is not None and self.answer is not None:
            return Action(self.answer, {"reason": "because"})
        return Action(WAIT)


class Proposer(AssistantPolicy):
    """Proposes once at its first turn; in execute mode takes ``execute_actions`` and reports."""

    def __init__(self, execute_actions: list[Action] | None = None, report: bool = True) -> None:
        self.execute_actions = list(execute_actions or [])
        self.report = report
        self.proposed = False
        self.tasks: list[Task] = []
        self.observations: list[AssistantObservation] = []

    async def observe(self, observation: AssistantObservation | None, previous: ToolResult | None) -> Action:
        if observation is not None:
            self.observations.append(observation)
        if not self.proposed:
            self.proposed = True
            return Action(SEND_MESSAGE, {"content": "Reply to Ann that Thursday works."})
        return Action(ASSISTANT_WAIT)

    async def execute(self, task: Task | None, previous: ToolResult | None) -> Action:
        if task is not None:
            self.tasks.append(task)
        if self.execute_actions:
            return self.execute_actions.pop(0)
        if self.report:
            return Action(SEND_MESSAGE, {"content": "Done."})
        return Action("email__list_emails")


def test_oracle_turns_time_and_modes() -> None:
    result = run_episode(SCENARIO, OracleUser(SCENARIO), OracleAssistant(SCENARIO))
    assert result.success and result.ended == "idle"
    shape = [(s.turn, s.actor, s.mode, s.action.tool) for s in result.steps]
    assert shape[:2] == [(1, "user", None, WAIT), (1, "assistant", "observe", ASSISTANT_WAIT)]
    # both waited at turn 1: time jumped to the email at +5m, delivered before the user's step at turn 2
    log = result.env.log.entries
    arrival = next(e for e in log if e.actor == "env")
    assert arrival.time == SCENARIO.start + timedelta(minutes=5) and arrival.turn == 2
    assert (log[arrival.index + 1].actor, log[arrival.index + 1].tool) == ("user", "open_app")
    accepted_turn = next(s.turn for s in result.steps if s.action.tool == "accept_proposal")
    execute = [s for s in result.steps if s.mode == "execute"]
    assert {s.turn for s in execute} == {accepted_turn}
    assert [s.action.tool for s in execute] == ["email__reply_to_email", SEND_MESSAGE]


def test_rejection_returns_to_observe_without_executing() -> None:
    assistant = Proposer()
    result = run_episode(SCENARIO, Answering("reject_proposal"), assistant)
    assert not result.success and assistant.tasks == []
    assert result.env.agent_ui.state.proposals[0].status == "rejected"
    # the assistant observed again after the rejection and saw the user's answer
    assert any("rejected" in " ".join(o.notifications) for o in assistant.observations)


def test_acceptance_starts_execute_with_the_task() -> None:
    assistant = Proposer([Action("email__reply_to_email", {"email_id": "e1", "content": "ok"})])
    result = run_episode(SCENARIO, Answering("accept_proposal"), assistant)
    (task,) = assistant.tasks
    assert task.proposal == "Reply to Ann that Thursday works." and task.answer == "because"
    assert [s.mode for s in result.steps if s.actor == "assistant"][1:3] == ["execute", "execute"]
    assert result.env.agent_ui.state.messages[0].content == "Done."


def test_unanswered_proposal_expires_after_its_turns() -> None:
    settings = EpisodeSettings(proposal_ttl_turns=2, max_turns=6)
    result = run_episode(SCENARIO, Answering(None), Proposer(), settings)
    assert result.expired_proposals == ["proposal-1"]
    assert result.env.agent_ui.state.proposals[0].status == "expired"
    # while the proposal waited, the assistant held back; after expiry it observed again
    turns = [s.turn for s in result.steps if s.actor == "assistant"]
    assert turns[0] == 1 and 2 not in turns and 3 in turns


def test_execute_stops_at_its_step_limit() -> None:
    settings = EpisodeSettings(execute_steps=3)
    result = run_episode(SCENARIO, Answering("accept_proposal"), Proposer(report=False), settings)
    assert len([s for s in result.steps if s.mode == "execute"]) == 3


class Reader(AssistantPolicy):
    """Reads forever in observe mode, and tries to write once."""

    async def observe(self, observation: AssistantObservation | None, previous: ToolResult | None) -> Action:
        if observation is not None:
            return Action("email__delete_email", {"email_id": "e1"})
        return Action("email__list_emails")

    async def execute(self, task: Task | None, previous: ToolResult | None) -> Action:
        return Action(SEND_MESSAGE, {"content": "-"})


def test_observe_stops_at_its_step_limit_and_refuses_writes() -> None:
    settings = EpisodeSettings(observe_steps=4, max_turns=2)
    result = run_episode(SCENARIO, Answering(None), Reader(), settings)
    first_turn = [s for s in result.steps if s.actor == "assistant" and s.turn == 1]
    assert len(first_turn) == 4
    assert not first_turn[0].ok and "only in execute mode" in first_turn[0].observation
    assert result.ended == "max_turns" and result.turns == 2
    assert "e1" in result.env.snapshot()["email"]["emails"]


def test_turn_duration_when_someone_acts() -> None:
    settings = EpisodeSettings(turn_duration=timedelta(minutes=3), max_turns=2)
    result = run_episode(SCENARIO, Answering(None), Reader(), settings)
    times = sorted({e.time for e in result.env.log.entries if e.actor == "assistant"})
    assert times[1] - times[0] == timedelta(minutes=3)


def test_the_user_sees_only_what_is_offered() -> None:
    user = Answering(None)
    run_episode(SCENARIO, user, Proposer(), EpisodeSettings(max_turns=3))
    assert "accept_proposal" not in user.views[0].tool_names
    assert user.views[1].pending_proposal == "Reply to Ann that Thursday works."
    assert "accept_proposal" in user.views[1].tool_names


def test_nothing_can_happen_ends_the_episode_early() -> None:
    data = base()
    data["events"] = []
    data["oracle"]["user"] = []
    data["oracle"]["interventions"][0]["when"] = None
    data["oracle"]["interventions"][0]["actions"][0]["args"]["email_id"] = "e1"
    data["goals"][0]["checks"][0]["action"]["args"]["email_id"] = "e1"
    scenario = parse(data)
    result = run_episode(scenario, Answering(None), SilentAssistant())
    assert result.ended == "idle" and result.turns == 1


def test_same_seed_same_trajectory_byte_for_byte() -> None:
    def trajectory() -> str:
        settings = EpisodeSettings(env=SCENARIO_CONFIG)
        result = run_episode(SCENARIO, OracleUser(SCENARIO), OracleAssistant(SCENARIO), settings)
        return write_trajectory(result.trajectory(seed=SCENARIO_CONFIG.seed))  # the file's very text

    assert trajectory() == trajectory()


def test_jumps_over_idle_time_bring_no_pile_of_noise() -> None:
    data = base()
    data["events"][0]["at"] = "day+2 09:00"  # two idle days until Ann writes
    scenario = parse(data)
    settings = EpisodeSettings(env=EnvConfig(seed=3, noise_rate_per_minute=2.0))
    result = run_episode(scenario, OracleUser(scenario), OracleAssistant(scenario), settings)
    assert result.success
    noise = [e for e in result.env.log.entries if e.event_id and e.event_id.startswith("noise-")]
    active_minutes = result.turns  # about one simulated minute per active turn
    assert len(noise) < 10 * active_minutes  # not the ~5,760 two idle days would bring
    arrival = next(e for e in result.env.log.entries if e.event_id == "ann_asks")
    assert arrival.time == scenario.start + timedelta(days=2)


def test_the_verdict_serialises_every_field_of_goals_and_checks() -> None:
    """The trajectory's outcome holds what ``dataclasses.asdict`` gives (built without its deep copies)."""
    from dataclasses import asdict

    result = run_episode(SCENARIO, OracleUser(SCENARIO), SilentAssistant())  # fails: checks with details
    goals = result.to_dict()["outcome"]["goals"]
    assert goals and any(not check["passed"] for goal in goals for check in goal["checks"])
    assert json.dumps(goals) == json.dumps([asdict(goal) for goal in result.outcome.goals])
