"""The trajectory file: written and read back the same, older formats upgraded, newer and damaged ones
refused with the file and the field named.

``format1/`` holds two run folders written by PARE before format 2 (commit d9eea69, the oracle and the
scripted model-backed actors of ``tests/viewer/runs.py`` over two scenarios, one run each).
"""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest

from pare.agents.policy import SilentAssistant
from pare.apps.harm import harm_by_index
from pare.bench.episode import EpisodeSettings, run_episode
from pare.errors import UserInputError
from pare.results.records import summarize
from pare.results.run_folder import load_run
from pare.results.trajectory import (
    TRAJECTORY_FORMAT,
    Trajectory,
    final_state,
    parse_trajectory,
    read_trajectory,
    state_hash,
    write_trajectory,
)
from pare.scenarios.build import build_environment
from pare.scenarios.checks import evaluate
from pare.scenarios.library import get_scenario
from pare.scenarios.oracle import OracleAssistant, OracleUser
from pare.scenarios.side_effects import assistant_changes
from pare.sim.log import LogEntry
from pare.viewer import Catalog, Site
from tests.bench.test_episode import Answering, Proposer
from tests.scenarios.helpers import base, parse
from tests.viewer.runs import WORLD_SCENARIO

FORMAT_1 = Path(__file__).parent / "format1"
SCENARIO = "dentist_moves_checkup"


def _played(scenario_id: str = SCENARIO) -> Trajectory:
    scenario = get_scenario(scenario_id)
    result = run_episode(scenario, OracleUser(scenario), OracleAssistant(scenario))
    return result.trajectory(label="oracle", run=2, seed=7, scenario_hash="abc")


def _format_1(kind: str, scenario_id: str = SCENARIO) -> Path:
    return FORMAT_1 / kind / "trajectories" / scenario_id / "run-1.json"


def test_a_written_trajectory_reads_back_the_same() -> None:
    trajectory = _played()
    text = write_trajectory(trajectory)
    read = parse_trajectory(text)
    assert read == trajectory and write_trajectory(read) == text
    assert json.loads(text)["format"] == TRAJECTORY_FORMAT
    assert (read.label, read.run, read.seed, read.scenario_hash) == ("oracle", 2, 7, "abc")
    entries = read.log_entries()
    assert all(isinstance(entry, LogEntry) for entry in entries)
    assert [entry.to_dict() for entry in entries] == [
        entry.to_dict() for entry in build_and_play_log(SCENARIO)
    ]


def build_and_play_log(scenario_id: str) -> list[LogEntry]:
    scenario = get_scenario(scenario_id)
    return run_episode(scenario, OracleUser(scenario), OracleAssistant(scenario)).env.log.entries


def test_the_final_state_is_the_start_with_the_diff_and_checks_the_start() -> None:
    scenario = get_scenario(SCENARIO)
    result = run_episode(scenario, OracleUser(scenario), OracleAssistant(scenario))
    trajectory = parse_trajectory(write_trajectory(result.trajectory()))
    start = build_environment(scenario).snapshot()
    assert trajectory.start_state_hash == state_hash(start)
    assert final_state(trajectory, start) == result.env.snapshot()
    changed = build_environment(scenario).snapshot()
    changed["calendar"]["events"].clear()
    with pytest.raises(ValueError, match="not the data this episode started from"):
        final_state(trajectory, changed)


@pytest.mark.parametrize(
    ("scenario_id", "by_hand"),
    [(SCENARIO, False), ("partner_rent_ceiling_prunes_saved_flats", False), (WORLD_SCENARIO, True)],
)
def test_the_checks_evaluated_again_on_the_stored_trajectory_give_its_verdict(
    scenario_id: str, by_hand: bool
) -> None:
    """What re-grading needs is kept: the log, the whole attribution (who had a hand in each place, what
    was removed) and the final state as start + diff give the episode's own verdict and side effects."""
    scenario = get_scenario(scenario_id)
    if by_hand:  # the user does the work by hand: the verdict turns on who had a hand in what
        settings = EpisodeSettings(max_turns=EpisodeSettings().max_turns + len(scenario.by_hand().user))
        result = run_episode(scenario, OracleUser(scenario, scenario.by_hand()), SilentAssistant(), settings)
    else:
        result = run_episode(scenario, OracleUser(scenario), OracleAssistant(scenario))
    trajectory = parse_trajectory(write_trajectory(result.trajectory()))
    start = build_environment(scenario).snapshot()
    final = final_state(trajectory, start)
    attribution = trajectory.attribution_state()
    again = evaluate(scenario, trajectory.log_entries(), final, attribution=attribution)
    env = result.env
    played = evaluate(scenario, env.log.entries, env.snapshot(), attribution=env.attribution)
    assert again == played and again.success == (not by_hand) and again.user_did_work == by_hand
    harm_of = harm_by_index(trajectory.log_entries())
    assert assistant_changes(start, final, attribution, harm_of=harm_of) == result.changes


def test_a_format_1_file_cannot_give_the_whole_attribution() -> None:
    trajectory = read_trajectory(_format_1("oracle"))
    assert trajectory.marks and trajectory.removals is None
    with pytest.raises(ValueError, match="whole attribution"):
        trajectory.attribution_state()


def test_an_expired_proposal_keeps_the_turn_it_expired_in() -> None:
    settings = EpisodeSettings(max_turns=6, proposal_ttl_turns=2)
    result = run_episode(parse(base()), Answering(None), Proposer(), settings)  # never answered
    trajectory = parse_trajectory(write_trajectory(result.trajectory()))
    (proposal,) = [p for p in trajectory.proposals if p.status == "expired"]
    assert proposal.expired_at == result.expired_at[proposal.proposal_id] == proposal.turn + 2
    (record,) = [r for r in summarize(trajectory)["proposals"] if r.proposal_id == proposal.proposal_id]
    assert record.resolution == "expired"


@pytest.mark.parametrize("kind", ["oracle", "models"])
def test_a_format_1_file_is_upgraded_on_read(kind: str) -> None:
    file = _format_1(kind)
    raw = json.loads(file.read_text(encoding="utf-8"))
    assert raw["format"] == 1 and "proposals" not in raw
    trajectory = read_trajectory(file)
    assert trajectory.format == TRAJECTORY_FORMAT and trajectory.start_state_hash is None
    # the proposals come back from the steps and the log, with what the record said became of them
    (record,) = [r for r in load_run(FORMAT_1 / kind).records if r.scenario_id == SCENARIO]
    assert [(p.proposal_id, p.turn) for p in trajectory.proposals] == [
        (r.proposal_id, r.turn) for r in record.proposals
    ]
    assert [p.status for p in trajectory.proposals] == [r.resolution for r in record.proposals]
    # the record computed from the upgraded file is the one stored when it ran (but for what that PARE did
    # not count: irreversible calls, counted now from the log; wrong ones, unknown without side effects'
    # classes)
    summary = summarize(trajectory, usage=record.usage)
    assert summary.pop("wrong_irreversible_actions") == (None if trajectory.outcome.side_effects else 0)
    irreversible = summary.pop("irreversible_actions")
    assert (
        irreversible == 1 if kind == "oracle" else isinstance(irreversible, int)
    )  # the reply to the practice
    assert summary == {name: getattr(record, name) for name in summary}


def test_the_viewer_opens_a_format_1_run(tmp_path: Path) -> None:
    folder = tmp_path / "models"
    shutil.copytree(FORMAT_1 / "models", folder)
    page = Site(Catalog.open([folder])).page(f"c/models/e/{SCENARIO}/run-1.html")
    assert page is not None
    text = page.body.decode()
    assert 'class="bad problem"' not in text and 'id="goals"' in text
    assert "decision: accept" in text


def test_a_newer_format_is_refused_naming_the_file(tmp_path: Path) -> None:
    data = json.loads(write_trajectory(_played()))
    data["format"] = TRAJECTORY_FORMAT + 1
    file = tmp_path / "run-1.json"
    file.write_text(json.dumps(data), encoding="utf-8")
    with pytest.raises(UserInputError, match=f"trajectory format {TRAJECTORY_FORMAT + 1}, newer") as caught:
        read_trajectory(file)
    assert str(file) in str(caught.value)


@pytest.mark.parametrize(
    ("damage", "field"),
    [
        (lambda d: d["steps"][1]["action"].pop("tool"), "steps.1.action.tool"),
        (lambda d: d["log"][0].update(turn="soon"), "log.0.turn"),
        (lambda d: d["outcome"].update(success="maybe"), "outcome.success"),
        (lambda d: d["proposals"][0].update(status="forgotten"), "proposals.0.status"),
        (lambda d: d.update(surprise=1), "surprise"),
    ],
)
def test_a_damaged_file_names_the_file_and_the_field(tmp_path: Path, damage, field: str) -> None:  # type: ignore[no-untyped-def]
    data = json.loads(write_trajectory(_played()))
    damage(data)
    file = tmp_path / "run-1.json"
    file.write_text(json.dumps(data), encoding="utf-8")
    with pytest.raises(UserInputError) as caught:
        read_trajectory(file)
    message = str(caught.value)
    assert str(file) in message and f"{field}:" in message


def test_text_that_is_not_a_trajectory_is_named(tmp_path: Path) -> None:
    file = tmp_path / "run-1.json"
    file.write_text('{"format": 2, "steps": [', encoding="utf-8")
    with pytest.raises(UserInputError, match="not JSON") as caught:
        read_trajectory(file)
    assert str(file) in str(caught.value)


def test_check_results_keep_fields_this_reader_does_not_know() -> None:
    data = json.loads(write_trajectory(_played()))
    data["outcome"]["goals"][0]["checks"][0]["judge_answer"] = "YES"
    trajectory = parse_trajectory(json.dumps(data))
    check = trajectory.outcome.goals[0].checks[0]
    assert check.model_extra == {"judge_answer": "YES"}
    assert (
        json.loads(write_trajectory(trajectory))["outcome"]["goals"][0]["checks"][0]["judge_answer"] == "YES"
    )


@pytest.mark.parametrize("value", [float("nan"), float("inf"), "a lone \ud800 surrogate"])
def test_a_value_no_json_file_can_hold_is_refused_not_rewritten(value: object) -> None:
    trajectory = _played()
    step = trajectory.steps[0].model_copy(
        update={"action": trajectory.steps[0].action.model_copy(update={"args": {"x": value}})}
    )
    with pytest.raises(ValueError, match="cannot be written as JSON"):
        write_trajectory(trajectory.model_copy(update={"steps": [step, *trajectory.steps[1:]]}))
    # a text that only mentions them is written as it is
    step = step.model_copy(update={"action": step.action.model_copy(update={"args": {"x": "NaN Infinity"}})})
    assert parse_trajectory(write_trajectory(trajectory.model_copy(update={"steps": [step]}))).steps == [step]
