"""pare calibrate: proposals whose right answer is known, put to a user at the oracle's moment; the
decisions, their confusion table and rates, and a folder that resumes like a run.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import pytest

from pare.agents.actions import format_action
from pare.bench.calibration.cases import CASE_KINDS, calibration_cases
from pare.bench.calibration.run import run_calibration
from pare.bench.runconfig import build_config
from pare.cli import main
from pare.errors import UserInputError
from pare.results.calibration import calibration_metrics, load_calibration, wilson
from pare.scenarios.library import get_scenario
from pare.testing import ChatServer, completion
from pare.testing.chat_server import conversation_role

# a proposal scenario with wrong variants and carried mutants, and one where no proposal is right
FLIGHT = "airline_retimes_flight_rebook_airport_van"
CART = "abandoned_cart_left_on_purpose_needs_nothing"
SCENARIOS = [FLIGHT, CART, "babysitter_for_anniversary_dinner"]


def _calibrate(tmp_path: Path, name: str, **config: Any) -> Any:
    data = {"scenarios": {"ids": SCENARIOS}, "output": str(tmp_path / name), **config}
    summary = run_calibration(build_config(data))
    return summary, calibration_metrics(load_calibration(summary.path))


# -- the cases ------------------------------------------------------------------------------------------
def test_every_kind_of_case_comes_with_the_answer_that_is_right() -> None:
    flight, cart = get_scenario(FLIGHT), get_scenario(CART)
    cases = calibration_cases(flight) + calibration_cases(cart)
    kinds = {case.kind for case in cases}
    assert kinds == set(CASE_KINDS)
    right = {i.proposal for i in flight.oracle.interventions}
    for case in cases:
        assert case.expected == ("accept" if case.kind == "oracle" else "reject")
        assert (case.proposal in right) == (case.kind == "oracle")
    tempting = [case for case in cases if case.kind == "tempting"]
    assert tempting and all(case.scenario.id == CART for case in tempting)
    assert [c.case_id for c in cases] == [
        c.case_id for c in calibration_cases(flight) + calibration_cases(cart)
    ]


def test_a_mutant_case_says_the_wrong_value_in_the_proposal_itself() -> None:
    flight = get_scenario(FLIGHT)
    oracle_text = flight.oracle.interventions[0].proposal
    [later] = [c for c in calibration_cases(flight, kinds=("mutant",)) if c.name == "shift_time:1.2:+1h"]
    assert "08:30" in oracle_text and "08:30" not in later.proposal and "09:30" in later.proposal
    # only the value changed: the rest of the proposal is the oracle's
    assert later.proposal.replace("09:30", "08:30") == oracle_text


def test_cases_per_scenario_are_bounded() -> None:
    cart = get_scenario(CART)
    assert len(calibration_cases(cart, per_scenario=1)) == 1
    assert len(calibration_cases(cart, per_scenario=3)) == 3


# -- the done-when: the table separates the knowing user from the one who accepts everything -----------
def test_the_table_separates_the_strict_oracle_user_from_the_accept_everything_user(tmp_path: Path) -> None:
    _, strict = _calibrate(tmp_path, "strict", policies={"user": "oracle_strict"})
    _, accepting = _calibrate(tmp_path, "accept_all", policies={"user": "accept_all"})
    right, wrong = (sum(strict.confusion[e].values()) for e in ("accept", "reject"))
    assert right == 2 and wrong >= 10
    assert strict.confusion == {
        "accept": {"accept": right, "reject": 0, "no_answer": 0},
        "reject": {"accept": 0, "reject": wrong, "no_answer": 0},
    }
    assert accepting.confusion["reject"] == {"accept": wrong, "reject": 0, "no_answer": 0}
    assert strict.accept_when_wrong.value == 0.0 and accepting.accept_when_wrong.value == 1.0
    # the intervals do not overlap: the calibration tells them apart, not only their point estimates
    assert strict.accept_when_wrong.high is not None and accepting.accept_when_wrong.low is not None
    assert strict.accept_when_wrong.high < accepting.accept_when_wrong.low
    assert strict.reject_when_right.value == accepting.reject_when_right.value == 0.0
    assert {row.group for row in strict.by_kind} == set(CASE_KINDS)
    assert strict.not_reached == 0 and strict.failed == 0


def test_the_wilson_interval_is_exact_at_the_ends_and_wider_for_fewer_cases() -> None:
    assert (wilson(0, 10).low, wilson(10, 10).high) == (0.0, 1.0)
    assert wilson(0, 0).value is None
    few, many = wilson(2, 10), wilson(20, 100)
    assert few.low is not None and few.high is not None and many.low is not None and many.high is not None
    assert few.low < many.low < 0.2 < many.high < few.high
    assert round(wilson(5, 10).low or 0, 3) == 0.237  # the textbook value for 5 of 10


# -- resuming -------------------------------------------------------------------------------------------
def test_running_again_plays_nothing_recorded_and_another_user_is_refused(tmp_path: Path) -> None:
    first, _ = _calibrate(tmp_path, "strict", policies={"user": "oracle_strict"})
    assert first.played == first.planned > 0
    again, _ = _calibrate(tmp_path, "strict", policies={"user": "oracle_strict"})
    assert again.played == 0 and again.skipped == first.planned
    lines = (first.path / "decisions.jsonl").read_text(encoding="utf-8").splitlines()
    assert len(lines) == first.planned
    with pytest.raises(UserInputError, match=r"another configuration \(user\.policy"):
        _calibrate(tmp_path, "strict", policies={"user": "accept_all"})


# -- a model-backed user, offline -----------------------------------------------------------------------
def _careful_user(body: dict[str, Any]) -> Any:
    """A user model that looks at the clock once before answering, then rejects anything about plants
    (the unrelated proposals) and accepts the rest.
    """
    messages = [m for m in body.get("messages") or () if isinstance(m, dict)]
    assert conversation_role(messages) == "user"
    latest = str(messages[-1].get("content"))
    answered_before = [str(m.get("content")) for m in messages if m.get("role") == "assistant"]
    if "The assistant proposes" not in latest:
        text = format_action("wait", {}, "Nothing for me.")
    elif not any("get_current_time" in said for said in answered_before):
        text = format_action("get_current_time", {}, "Let me check the time first.")
    elif "plants" in latest:
        text = format_action("reject_proposal", {"reason": "Not now."}, "That has nothing to do with my day.")
    else:
        text = format_action("accept_proposal", {"reason": "Yes."}, "That is what I need.")
    return completion(text, prompt_tokens=40)


def test_a_user_model_is_calibrated_offline_with_what_it_looked_up(tmp_path: Path) -> None:
    out = tmp_path / "model"
    with ChatServer(_careful_user) as server:
        argv = ["calibrate", "-s", FLIGHT, "--case-kind", "oracle", "--case-kind", "unrelated"]
        argv += ["--user-model", "tiny-user", "--user-endpoint", server.base_url]
        argv += ["--set", "models.user.api_key_env=null", "--user-trust", "sceptical", "-o", str(out)]
        assert main([*argv, "--no-progress", "--format", "json"]) == 0
        systems = {str(r["messages"][0]["content"]) for r in server.requests}
    assert all("Be a sceptical user" in system for system in systems)  # the persona reached the model
    loaded = load_calibration(out)
    decisions = {r.kind: (r.decision, r.looked) for r in loaded.records}
    assert decisions == {"oracle": ("accept", 1), "unrelated": ("reject", 1)}
    metrics = calibration_metrics(loaded)
    assert metrics.user_trust == "sceptical" and metrics.label == "tiny-user (sceptical)"
    assert metrics.looked.value == 1.0 and metrics.after_looking == {"accept": 1, "reject": 1, "no_answer": 0}
    assert all(r.usage["calls"] >= 2 for r in loaded.records)
    assert loaded.manifest["protocol"]["overrides"] == {"user_trust": "sceptical"}
    trajectory = json.loads((out / loaded.records[0].trajectory).read_text(encoding="utf-8"))  # type: ignore[operator]
    assert trajectory["case"] == loaded.records[0].case_id and trajectory["steps"]
    # replayed from the folder's cache: the same decisions without the server
    assert (
        main(
            [
                *argv[:-2],
                "-o",
                str(tmp_path / "replay"),
                "--cache",
                "replay",
                "--set",
                f"cache_path={out / 'model_calls.sqlite'}",
                "--no-progress",
            ]
        )
        == 0
    )
    replayed = {r.kind: (r.decision, r.looked) for r in load_calibration(tmp_path / "replay").records}
    assert replayed == decisions


def test_a_user_that_never_answers_is_recorded_as_no_answer(tmp_path: Path) -> None:
    summary, metrics = _calibrate(
        tmp_path, "silent", policies={"user": "silent"}, scenarios={"ids": [FLIGHT]}
    )
    assert summary.played > 0 and metrics.no_answer.value == 1.0
    assert metrics.accept_when_wrong.value == 0.0 and metrics.reject_when_right.value == 0.0


# -- reports and the figure -----------------------------------------------------------------------------
def test_report_and_plot_read_calibration_folders(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    _calibrate(tmp_path, "strict", policies={"user": "oracle_strict"})
    _calibrate(tmp_path, "accept_all", policies={"user": "accept_all"})
    folders = [str(tmp_path / "strict"), str(tmp_path / "accept_all")]
    capsys.readouterr()
    assert main(["report", *folders, "--format", "markdown"]) == 0
    text = capsys.readouterr().out
    assert "## oracle_strict: protocol pare, user trust demanding" in text and "## accept_all" in text
    assert "| accept when wrong | 0.0% [0.0," in text and "| accept when wrong | 100.0% [" in text
    assert main(["report", *folders, "--format", "csv"]) == 0
    rows = capsys.readouterr().out.splitlines()
    assert rows[0].startswith("label,user_trust,grouping,group,cases,right")
    assert any(row.startswith("accept_all,demanding,kind,variant,") for row in rows)
    pytest.importorskip("matplotlib")
    assert main(["plot", *folders, "-o", str(tmp_path / "figs")]) == 0
    assert (tmp_path / "figs" / "calibration.png").stat().st_size > 0
    assert main(["report", folders[0], str(tmp_path)]) == 2  # a calibration and no run: refused
