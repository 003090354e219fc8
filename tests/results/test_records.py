"""From a played episode to its record: the decision analysis of each proposal, counts and usage."""

from __future__ import annotations

from pare.agents import ASSISTANT_WAIT, SEND_MESSAGE, WAIT, Action, AssistantPolicy, Task, UserPolicy
from pare.bench import EpisodeSettings, run_episode
from pare.env import AssistantObservation, ToolResult, UserView
from pare.results.records import summarize
from tests.scenarios.helpers import base, parse

SCENARIO = parse(base())


class ScriptedUser(UserPolicy):
    """Plays a fixed list of actions, one per step (then waits); ``answer`` stands for accepting or
    rejecting whatever proposal is pending at that moment.
    """

    def __init__(self, script: list[str]) -> None:
        self.script = list(script)

    async def step(self, view: UserView, previous: ToolResult | None) -> Action:
        tool = self.script.pop(0) if self.script else WAIT
        if tool == "look":
            return Action("open_app", {"app_name": "email"}) if view.app is None else Action("go_home")
        return Action(tool, {"reason": "ok"} if tool.endswith("_proposal") else {})


class ProposeAt(AssistantPolicy):
    """Proposes at the given observe turns (counting its own observe turns), reads once each turn."""

    def __init__(self, at: set[int]) -> None:
        self.at = at
        self.turn = 0
        self.step = 0

    async def observe(self, observation: AssistantObservation | None, previous: ToolResult | None) -> Action:
        if observation is not None:
            self.turn += 1
            self.step = 0
        self.step += 1
        if self.step == 1:
            return Action("email__list_emails")
        if self.step == 2 and self.turn in self.at:
            return Action(SEND_MESSAGE, {"content": f"Proposal at my turn {self.turn}"})
        return Action(ASSISTANT_WAIT)

    async def execute(self, task: Task | None, previous: ToolResult | None) -> Action:
        if task is not None:
            return Action("email__list_emails")
        return Action(SEND_MESSAGE, {"content": "Done."})


def _summary(user: list[str], at: set[int], **settings: int) -> dict[str, object]:
    result = run_episode(SCENARIO, ScriptedUser(user), ProposeAt(at), EpisodeSettings(**settings))
    return summarize(result.trajectory())


def test_direct_accept_and_direct_reject() -> None:
    # turn 1: user waits, assistant reads and proposes; turn 2: the user's first step answers it
    accepted = _summary([WAIT, "accept_proposal"], {1}, max_turns=3)
    (proposal,) = accepted["proposals"]  # type: ignore[misc]
    assert (proposal.decision, proposal.resolution, proposal.turn, proposal.answered_turn) == (
        "accept",
        "accepted",
        1,
        2,
    )
    rejected = _summary([WAIT, "reject_proposal"], {1}, max_turns=3)
    (proposal,) = rejected["proposals"]  # type: ignore[misc]
    assert (proposal.decision, proposal.resolution) == ("reject", "rejected")


def test_gather_context_then_accept() -> None:
    summary = _summary([WAIT, "look", "look", "accept_proposal"], {1}, max_turns=5)
    (proposal,) = summary["proposals"]  # type: ignore[misc]
    assert (proposal.decision, proposal.resolution) == ("gather_context", "accepted")
    assert proposal.user_steps_before_answer == 2 and proposal.answered_turn == 4


def test_gather_context_then_expired_and_truncated() -> None:
    expired = _summary(
        [WAIT, "look", WAIT, "look", "accept_proposal"], {1}, max_turns=6, proposal_ttl_turns=3
    )
    (proposal,) = expired["proposals"]  # type: ignore[misc]
    # it expired after the user's step of turn 4 (3 turns after turn 1): the accept in turn 5 came too late
    assert (proposal.decision, proposal.resolution, proposal.answered_turn) == (
        "gather_context",
        "expired",
        None,
    )
    assert proposal.user_steps_before_answer == 3

    truncated = _summary([WAIT, "look"], {1}, max_turns=2)
    (proposal,) = truncated["proposals"]  # type: ignore[misc]
    assert (proposal.decision, proposal.resolution) == ("gather_context", "truncated")


def test_a_proposal_in_the_last_turn_is_truncated() -> None:
    summary = _summary([], {2}, max_turns=2)
    (proposal,) = summary["proposals"]  # type: ignore[misc]
    assert (proposal.decision, proposal.resolution, proposal.user_steps_before_answer) == (
        "truncated",
        "truncated",
        0,
    )


def test_counts_turns_reads_and_writes() -> None:
    # turn 1 proposal accepted in turn 2 (execute reads once, then reports), observing again from turn 3
    summary = _summary([WAIT, "accept_proposal"], {1}, max_turns=4)
    assert summary["turns"] == 4 and summary["ended"] == "max_turns"
    # observe turns: 1 (proposal), 3 and 4; turn 2 is the execute turn
    assert summary["observe_turns"] == 3
    # reads: one list_emails per observe turn (3) and one in execute mode
    assert summary["read_actions"] == 4 and summary["observe_read_actions"] == 3
    assert summary["write_actions"] == 0
    assert summary["user_actions"] == 4
    assert summary["usage"] == {}  # no model behind these actors
