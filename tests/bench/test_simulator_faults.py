"""Simulator faults: scripted users that commit each fault are caught, and the oracle users never are.

The scenario is the book club one: Hannah buys paperbacks only; the oracle proposes the paperback with the
club code once she has opened Gwen's email; failing variants propose the hardcover and other near-misses.
"""

from __future__ import annotations

import csv
import io
import json
from pathlib import Path

import pytest

from pare.agents.policy import WAIT, Action, SilentAssistant, SilentUser
from pare.bench.episode import EpisodeResult, run_episode
from pare.bench.policies import PolicyContext
from pare.bench.simulator_faults import find_faults, matches, typed_facts
from pare.cli import main
from pare.env import ToolResult, UserView
from pare.results.records import SimulatorFault, classify_proposals
from pare.results.run_folder import load_run
from pare.scenarios.library import library
from pare.scenarios.loader import load_scenario
from pare.scenarios.model import Scenario
from pare.scenarios.oracle import BusyUser, OracleAssistant, OracleUser, SlowUser, UnrelatedAssistant

BENCH = Path(__file__).resolve().parents[2] / "src" / "pare" / "scenarios" / "bench"


@pytest.fixture(scope="module")
def book_club() -> Scenario:
    return load_scenario(BENCH / "book_club_pick_paperback.yaml")


class RejectingUser(OracleUser):
    """The oracle user who turns every proposal down."""

    async def step(self, view: UserView, previous: ToolResult | None) -> Action:
        if view.pending_proposal is not None:
            return Action("reject_proposal", {"reason": "No, thanks."})
        return await super().step(view, previous)


def rejecting_user(context: PolicyContext) -> RejectingUser:
    """The rejecting user as a policy factory, for ``pare run --user-policy``."""
    return RejectingUser(context.scenario)


class IgnoringUser(OracleUser):
    """The oracle user who never answers a proposal: it waits until the proposal expires."""

    async def step(self, view: UserView, previous: ToolResult | None) -> Action:
        if view.pending_proposal is not None:
            return Action(WAIT)
        return await super().step(view, previous)


class MakingThingsUpUser(OracleUser):
    """Orders by hand with a discount code no screen ever showed."""

    def __init__(self, scenario: Scenario) -> None:
        super().__init__(scenario, scenario.by_hand())
        checkout = self.steps[-1]
        assert checkout.tool == "checkout"
        self.steps[-1] = checkout.model_copy(update={"args": {"discount_code": "BRAMBLE2025"}})


def faults(scenario: Scenario, result: EpisodeResult) -> list[SimulatorFault]:
    return find_faults(scenario, result, classify_proposals(result.trajectory()))


def kinds(found: list[SimulatorFault]) -> list[str]:
    return [fault.kind for fault in found]


def test_the_oracle_and_its_slow_and_busy_users_commit_no_fault(book_club: Scenario) -> None:
    for user in (OracleUser(book_club), SlowUser(book_club), BusyUser(book_club)):
        result = run_episode(book_club, user, OracleAssistant(book_club))
        assert result.success and faults(book_club, result) == []


def test_passing_variants_commit_no_fault(book_club: Scenario) -> None:
    for variant in (v for v in book_club.variants if v.expect == "pass"):
        solution = book_club.solution(variant.id)
        result = run_episode(book_club, OracleUser(book_club, solution), OracleAssistant(book_club, solution))
        assert result.success and faults(book_club, result) == [], variant.id


def test_accepting_a_declared_near_miss_is_a_fault(book_club: Scenario) -> None:
    hardcover = book_club.solution("hardcover")
    result = run_episode(book_club, OracleUser(book_club, hardcover), OracleAssistant(book_club, hardcover))
    found = faults(book_club, result)
    assert not result.success and kinds(found) == ["accepted_wrong"]
    assert found[0].proposal_id == "proposal-1" and found[0].turn == 3


def test_accepting_an_unrelated_proposal_is_no_fault(book_club: Scenario) -> None:
    # a reminder to water the plants does not contradict Hannah's goal: the failure is the assistant's
    result = run_episode(book_club, OracleUser(book_club), UnrelatedAssistant(book_club))
    assert not result.success and [p.resolution for p in classify_proposals(result.trajectory())] == [
        "accepted"
    ]
    assert faults(book_club, result) == []


def test_rejecting_the_solutions_proposal_is_a_fault(book_club: Scenario) -> None:
    result = run_episode(book_club, RejectingUser(book_club), OracleAssistant(book_club))
    found = faults(book_club, result)
    assert kinds(found) == ["rejected_right"] and found[0].proposal_id == "proposal-1"


def test_rejecting_a_near_miss_is_no_fault(book_club: Scenario) -> None:
    hardcover = book_club.solution("hardcover")
    result = run_episode(
        book_club, RejectingUser(book_club, hardcover), OracleAssistant(book_club, hardcover)
    )
    assert faults(book_club, result) == []


def test_letting_the_solutions_proposal_expire_is_a_stall(book_club: Scenario) -> None:
    result = run_episode(book_club, IgnoringUser(book_club), OracleAssistant(book_club))
    found = faults(book_club, result)
    assert kinds(found) == ["stalled"] and "expired" in found[0].detail


def test_never_taking_the_step_help_waits_for_is_a_stall(book_club: Scenario) -> None:
    result = run_episode(book_club, SilentUser(), OracleAssistant(book_club))
    found = faults(book_club, result)
    assert kinds(found) == ["stalled"] and "email__open_email" in found[0].detail


def test_doing_the_task_alone_without_accepting_is_no_fault(book_club: Scenario) -> None:
    result = run_episode(book_club, OracleUser(book_club, book_club.by_hand()), SilentAssistant())
    assert not result.success and result.outcome.user_did_work
    assert faults(book_club, result) == []


def test_doing_the_task_by_hand_after_accepting_is_a_fault(book_club: Scenario) -> None:
    result = run_episode(book_club, OracleUser(book_club, book_club.by_hand()), UnrelatedAssistant(book_club))
    found = faults(book_club, result)
    assert kinds(found) == ["did_by_hand"] and "add_to_cart" in found[0].detail


def test_typing_a_fact_never_shown_is_a_fault(book_club: Scenario) -> None:
    result = run_episode(book_club, MakingThingsUpUser(book_club), SilentAssistant())
    found = faults(book_club, result)
    assert kinds(found) == ["unseen_fact"] and "bramble2025" in found[0].detail


def test_matching_wants_the_same_figures_and_most_words() -> None:
    oracle = "Shall I order one paperback of The Salt Orchard ($12.99) with the code BRAMBLE10?"
    assert matches("Shall I order one paperback of The Salt Orchard ($12.99) with the code BRAMBLE10", oracle)
    assert not matches(oracle.replace("12.99", "24.00"), oracle)  # another figure: another proposal
    assert not matches("Shall I order the book?", oracle)  # too few words in common


def test_in_a_no_proposal_scenario_only_a_declared_near_miss_accepted_is_a_fault() -> None:
    scenario = load_scenario(BENCH / "newsletter_coupon_for_unneeded_category_needs_nothing.yaml")
    eager = scenario.solution("orders_bistro_set")
    result = run_episode(scenario, OracleUser(scenario, eager), OracleAssistant(scenario, eager))
    assert not result.success and kinds(faults(scenario, result)) == ["accepted_wrong"]
    # an unrelated offer fails the scenario's quiet goal by being made, whatever the user answers
    unrelated = run_episode(scenario, OracleUser(scenario), UnrelatedAssistant(scenario))
    assert not unrelated.success and faults(scenario, unrelated) == []
    quiet = run_episode(scenario, OracleUser(scenario), SilentAssistant())
    assert quiet.success and faults(scenario, quiet) == []


def test_a_run_records_the_faults_and_reports_them_in_every_format(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setenv("COLUMNS", "240")
    folder = tmp_path / "run"
    user = f"{__name__}:rejecting_user"
    arguments = ["-s", "book_club_pick_paperback", "--runs", "1", "--no-progress", "--output", str(folder)]
    assert main(["run", *arguments, "--user-policy", user]) == 0
    [record] = load_run(folder).records
    assert [fault.kind for fault in record.simulator_faults] == ["rejected_right"]
    trajectory = json.loads((folder / str(record.trajectory)).read_text())
    assert [fault["kind"] for fault in trajectory["simulator_faults"]] == ["rejected_right"]
    capsys.readouterr()

    # one failure, with a fault; no episode left without one: no success rate to give
    assert main(["report", str(folder), "--section", "simulator", "--format", "markdown"]) == 0
    markdown = capsys.readouterr().out
    assert (
        "## User simulator faults" in markdown
        and "| 100.0% (1/1) | n/a | 0 | 0 | 1 | 0 | 0 | 0 |" in markdown
    )
    assert main(["report", str(folder), "--section", "simulator"]) == 0
    assert "User simulator faults" in capsys.readouterr().out
    assert main(["report", str(folder), "--section", "simulator", "--format", "latex"]) == 0
    assert r"100.0\% (1/1)" in capsys.readouterr().out
    assert main(["report", str(folder), "--format", "csv"]) == 0
    row = next(csv.DictReader(io.StringIO(capsys.readouterr().out)))
    assert row["simulator.failures_with_fault"] == "1" and row["simulator.fault.rejected_right"] == "1"
    assert main(["report", str(folder), "--format", "json"]) == 0
    [data] = json.loads(capsys.readouterr().out)["configurations"]
    assert data["simulator"]["failure_fault_share"] == 1.0


def test_dates_times_and_paths_are_read_whole_and_only_figures_count_as_facts() -> None:
    typed = (
        "Call 555-0142 at 14:30 on 2025-09-09T18:30:00+01:00 with BRAMBLE2025; x@y.com; /Scans/scan_2041.pdf"
    )
    assert typed_facts({"content": typed, "count": 2}) == {
        "555-0142",
        "bramble2025",
        "x@y.com",
        "scans/scan_2041.pdf",
    }


def test_no_solution_the_library_declares_right_is_taken_for_a_simulator_fault() -> None:
    """Every scenario's oracle and passing variants, played by the oracle users: not one fault."""
    for scenario in library().values():
        for name in [None, *(v.id for v in scenario.variants if v.expect == "pass")]:
            solution = scenario.solution(name)
            user, assistant = OracleUser(scenario, solution), OracleAssistant(scenario, solution)
            result = run_episode(scenario, user, assistant)
            assert faults(scenario, result) == [], (scenario.id, name)
