"""A person in the user's seat at the terminal (``pare play``): scripted lines play the person; the
episode is recorded as a run that reports and the viewer read, and a session left early records nothing.
"""

from __future__ import annotations

import asyncio
import io
import json
import signal
import subprocess
import sys
import time
from collections.abc import Callable, Iterator
from pathlib import Path

import pytest
from rich.console import Console

from pare.agents.human_input import SeatLeft
from pare.agents.terminal_user import TerminalUser
from pare.bench.play import PLAY_SETTINGS, Seat, play, prepare, record
from pare.bench.runconfig import build_config
from pare.cli import main
from pare.errors import UserInputError
from pare.results.run_folder import load_run
from pare.testing import ChatServer, proactive_play
from pare.viewer import Catalog, Site

SCENARIO = "dentist_moves_checkup"
# The oracle's user steps (the email arrives in turn 1), the proposal accepted with no reason, then waits.
ORACLE_PATH = ["1", "email", 'open_email {"email_id": "email-checkup-moves"}', "wait", "accept_proposal", ""]


def _lines(lines: list[str]) -> Callable[[str], str]:
    """An input source that answers each prompt with the next line, then ends (EOF) when they run out."""
    remaining: Iterator[str] = iter(lines)

    def read(prompt: str) -> str:
        try:
            return next(remaining)
        except StopIteration:
            raise EOFError from None

    return read


def _seat(folder: Path, scenario: str = SCENARIO, **settings: object) -> Seat:
    overrides = [("scenarios", {"ids": [scenario]}), ("output", str(folder)), *PLAY_SETTINGS]
    overrides += list(settings.items())
    return prepare(build_config({}, overrides=overrides))


def _console() -> Console:
    return Console(file=io.StringIO(), width=120, record=True)


def _play(seat: Seat, lines: list[str], console: Console | None = None) -> Path:
    scenario = seat.plan.scenario
    user = TerminalUser(
        console or _console(), _lines(lines), persona=scenario.user.persona, goal=scenario.user.goal
    )
    output = asyncio.run(play(seat, user))
    return record(seat, output)


def test_a_person_plays_the_oracle_path_and_the_episode_is_recorded_as_a_human_run(tmp_path: Path) -> None:
    console = _console()
    folder = _play(_seat(tmp_path / "run"), [*ORACLE_PATH, *["wait"] * 10], console)

    loaded = load_run(folder)
    assert loaded.label == "oracle (user human)"
    assert loaded.manifest["policies"]["user"] == "human"
    (episode,) = loaded.records
    assert episode.complete and episode.success and episode.key == (SCENARIO, 1)
    assert [p.resolution for p in episode.proposals] == ["accepted"]
    trajectory = json.loads((folder / str(episode.trajectory)).read_text(encoding="utf-8"))
    assert trajectory["user"] == "human"
    user_tools = [step["action"]["tool"] for step in trajectory["steps"] if step["actor"] == "user"]
    assert user_tools[:5] == ["open_app", "open_email", "wait", "accept_proposal", "wait"]

    site = Site(Catalog.open([folder]))  # pare view shows it like any episode
    (configuration,) = site.catalog.configurations
    page = site.page(f"c/{configuration.cid}/e/{SCENARIO}/run-1.html")
    assert page is not None
    html = page.body.decode("utf-8")
    assert "damaged" not in html and html.count('class="step step-user') == len(user_tools)

    shown = console.export_text()
    assert "You are the user" in shown and "Sam Rivera" in shown  # the persona and the goal come first
    assert "Current app: email; screen: Detail(email_id='email-checkup-moves')" in shown  # the model's text
    assert "The assistant proposes" in shown
    assert "The session is over after turn" in shown


def test_slips_are_explained_and_asked_again_without_costing_a_turn(tmp_path: Path) -> None:
    console = _console()
    slips = ["", "open_mail", "42", "open_app {app_name: email}", "help"]
    folder = _play(_seat(tmp_path / "run", **{"protocol.max_turns": 2}), [*slips, "wait", "wait"], console)

    shown = console.export_text()
    assert "Did you mean 'open_app'" in shown
    assert "There is no action 42 on this screen" in shown
    assert "must be one JSON object" in shown
    assert "Each turn you take one action" in shown  # help
    assert "Traceback" not in shown
    trajectory = json.loads(next((folder / "trajectories").rglob("run-1.json")).read_text(encoding="utf-8"))
    user_tools = [step["action"]["tool"] for step in trajectory["steps"] if step["actor"] == "user"]
    assert user_tools == ["wait"] * trajectory["turns"]  # the slips were not played


def test_a_required_argument_left_empty_is_asked_again(tmp_path: Path) -> None:
    console = _console()
    # menu 1 on the home screen is open_app: its app_name left empty, then given
    _play(_seat(tmp_path / "run", **{"protocol.max_turns": 1}), ["1", "", "email"], console)
    assert "'app_name' is required" in console.export_text()


def test_each_session_adds_the_next_run_and_the_plan_grows_with_the_scenarios_played(tmp_path: Path) -> None:
    folder = tmp_path / "run"
    _play(_seat(folder), [*ORACLE_PATH, *["wait"] * 10])
    second = _seat(folder)
    assert second.plan.run == 2 and second.plan.seed != _seat(tmp_path / "other").plan.seed
    _play(second, ["wait"] * 10)
    _play(_seat(folder, "five_a_side_kickoff_moved"), ["wait"] * 10)

    loaded = load_run(folder)
    assert loaded.runs == 2
    assert sorted(loaded.planned) == [
        ("dentist_moves_checkup", 1),
        ("dentist_moves_checkup", 2),
        ("five_a_side_kickoff_moved", 1),
        ("five_a_side_kickoff_moved", 2),
    ]
    assert [(r.scenario_id, r.run, r.success) for r in loaded.records] == [
        ("dentist_moves_checkup", 1, True),
        ("dentist_moves_checkup", 2, False),  # the person only waited
        ("five_a_side_kickoff_moved", 1, False),
    ]


def test_leaving_records_nothing(tmp_path: Path) -> None:
    seat = _seat(tmp_path / "run")
    user = TerminalUser(_console(), _lines(["1", "email", "quit"]))
    with pytest.raises(SeatLeft):
        asyncio.run(play(seat, user))
    assert not seat.folder.exists()  # nothing is written before the episode ends


def test_pare_play_at_the_terminal_then_pare_report_reads_it(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    folder = tmp_path / "run"
    monkeypatch.setattr("sys.stdin", io.StringIO("\n".join([*ORACLE_PATH, *["wait"] * 10]) + "\n"))
    assert main(["play", SCENARIO, "-o", str(folder)]) == 0
    out = capsys.readouterr().out
    assert "success: every goal met" in out
    assert f"recorded as run 1 in {folder}" in out
    assert main(["report", str(folder), "--format", "json"]) == 0
    report = json.loads(capsys.readouterr().out)
    assert json.dumps(report).count("oracle (user human)") >= 1


def test_pare_play_left_early_says_nothing_was_recorded(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    monkeypatch.setattr("sys.stdin", io.StringIO("1\nemail\n"))  # the input ends: the person is gone
    assert main(["play", SCENARIO, "-o", str(tmp_path / "run")]) == 1
    assert "nothing was recorded" in capsys.readouterr().out
    assert not (tmp_path / "run").exists()


def test_pare_play_against_a_model_assistant_records_its_usage(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setenv("PARE_PLAY_TEST_KEY", "not-a-real-key")
    folder = tmp_path / "run"
    lines = ["wait", "accept_proposal", "", *["wait"] * 10]
    monkeypatch.setattr("sys.stdin", io.StringIO("\n".join(lines) + "\n"))
    with ChatServer(proactive_play()) as assistant:
        argv = ["play", SCENARIO, "-o", str(folder), "--assistant-model", "test-assistant"]
        argv += [
            "--assistant-endpoint",
            assistant.base_url,
            "--set",
            "models.assistant.api_key_env=PARE_PLAY_TEST_KEY",
        ]
        assert main(argv) == 0
    loaded = load_run(folder)
    assert loaded.label == "test-assistant (user human)"
    (episode,) = loaded.records
    assert [p.resolution for p in episode.proposals] == ["accepted"]
    assert episode.usage["observe"].calls >= 1 and "user" not in episode.usage


def test_pare_run_refuses_the_human_user_before_making_a_folder(tmp_path: Path) -> None:
    folder = tmp_path / "run"
    assert main(["run", "-s", SCENARIO, "--user-policy", "human", "-o", str(folder), "--no-progress"]) == 2
    assert not folder.exists()


def test_pare_play_refuses_a_selection_of_other_than_one_scenario_and_a_user_model(tmp_path: Path) -> None:
    with pytest.raises(UserInputError, match="no scenario 'no_such_scenario'"):
        _seat(tmp_path / "run", "no_such_scenario")
    two = [("scenarios", {"ids": [SCENARIO, "five_a_side_kickoff_moved"]}), *PLAY_SETTINGS]
    with pytest.raises(UserInputError, match="one scenario at a time; the selection holds 2"):
        prepare(build_config({}, overrides=two))
    assert main(["play", SCENARIO, "-o", str(tmp_path / "run"), "--set", "models.user.model=x"]) == 2


@pytest.mark.parametrize("where", ["terminal", "browser"])
def test_ctrl_c_stops_the_session_at_once_and_records_nothing(tmp_path: Path, where: str) -> None:
    folder = tmp_path / "run"
    command = [sys.executable, "-u", "-m", "pare", "play", SCENARIO, "-o", str(folder)]
    ready = "Turn 1 of" if where == "terminal" else "http://127.0.0.1:"
    if where == "browser":
        command.append("--browser")
    with subprocess.Popen(
        command, stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True
    ) as process:
        assert process.stdout is not None
        seen = []
        for line in process.stdout:
            seen.append(line)
            if ready in line:
                break
        time.sleep(0.5)  # the person is being asked (a blocking read at the terminal)
        process.send_signal(signal.SIGINT)
        try:
            code = process.wait(timeout=20)
        finally:
            process.kill()
        rest = process.stdout.read()
    assert code == 130, "".join(seen) + rest
    assert "nothing was recorded" in rest
    assert "Traceback" not in rest
    assert not folder.exists()


def test_a_folder_the_episode_could_not_be_recorded_in_is_refused_before_the_person_plays(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    folder = tmp_path / "oracle"
    assert main(["run", "-s", SCENARIO, "--runs", "1", "-o", str(folder), "--no-progress"]) == 0
    capsys.readouterr()
    assert main(["play", SCENARIO, "-o", str(folder)]) == 2
    said = capsys.readouterr()
    assert "holds runs of another configuration" in said.err
    assert "Turn 1" not in said.out  # refused before the first turn


def test_two_sessions_started_together_keep_both_episodes(tmp_path: Path) -> None:
    folder = tmp_path / "run"
    first, second = _seat(folder), _seat(folder)
    assert first.plan.run == second.plan.run == 1
    _play(first, [*ORACLE_PATH, *["wait"] * 10])
    _play(second, ["wait"] * 10)  # finished later: recorded as run 2
    loaded = load_run(folder)
    assert [(r.run, r.success, r.trajectory) for r in loaded.records] == [
        (1, True, f"trajectories/{SCENARIO}/run-1.json"),
        (2, False, f"trajectories/{SCENARIO}/run-2.json"),
    ]
    assert (
        json.loads((folder / f"trajectories/{SCENARIO}/run-2.json").read_text(encoding="utf-8"))["run"] == 2
    )
    assert loaded.runs == 2
