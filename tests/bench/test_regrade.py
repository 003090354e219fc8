"""`pare regrade`: a run's stored trajectories judged again with today's checks, into a new run folder that
names the original, keeps each episode's old verdict and refuses what it cannot judge honestly."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest

from pare.cli import main
from pare.results.run_folder import load_run
from pare.scenarios.library import BENCH_DIR
from pare.testing import ChatServer, completion
from pare.viewer import Catalog, Site

SCENARIOS = ("dentist_moves_checkup", "five_a_side_kickoff_moved")


@pytest.fixture(autouse=True)
def wide(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("COLUMNS", "240")


@pytest.fixture
def played(tmp_path: Path) -> tuple[Path, Path]:
    """An oracle run (two runs each) of copies of two library scenarios: (the run, the scenario folder)."""
    folder = tmp_path / "scenarios"
    folder.mkdir()
    for scenario_id in SCENARIOS:
        shutil.copy(BENCH_DIR / f"{scenario_id}.yaml", folder)
    run = tmp_path / "run"
    argv = ["run", "--scenario-path", str(folder), "--runs", "2", "-o", str(run), "--no-progress"]
    assert main(argv) == 0
    return run, folder


def _edit(folder: Path, scenario_id: str, old: str, new: str) -> None:
    file = folder / f"{scenario_id}.yaml"
    text = file.read_text(encoding="utf-8")
    assert old in text
    file.write_text(text.replace(old, new, 1), encoding="utf-8")


def test_a_fixed_check_changes_the_verdicts_and_the_new_run_says_what_changed(
    played: tuple[Path, Path], capsys: pytest.CaptureFixture[str]
) -> None:
    run, folder = played
    # today's check wants the check-up an hour later than the oracle books it: its episodes now fail
    old, new = "            start_datetime: day+3 07:45\n", "            start_datetime: day+3 08:45\n"
    _edit(folder, "dentist_moves_checkup", old, new)
    capsys.readouterr()
    assert main(["regrade", str(run), "--scenario-path", str(folder)]) == 0
    out = capsys.readouterr().out
    assert "4 episodes re-graded" in out and "2 verdicts changed" in out
    assert "dentist_moves_checkup run 1: success -> failure (checkup_moved pass -> fail)" in out
    regraded = run.with_name("run-regraded")
    loaded = load_run(regraded)
    assert loaded.manifest["regraded_from"]["path"] == str(run.resolve())
    before = loaded.manifest["regraded_from"]["scenarios"]
    assert before["dentist_moves_checkup"] != loaded.manifest["plan"]["scenarios"]["dentist_moves_checkup"]
    assert (
        before["five_a_side_kickoff_moved"]
        == loaded.manifest["plan"]["scenarios"]["five_a_side_kickoff_moved"]
    )
    records = {record.key: record for record in loaded.records}
    dentist = records[("dentist_moves_checkup", 1)]
    assert not dentist.success and dentist.regraded_from is not None and dentist.regraded_from.success
    assert dentist.goals["checkup_moved"] is False and dentist.regraded_from.goals["checkup_moved"] is True
    assert records[("five_a_side_kickoff_moved", 2)].success
    # the old and the new scores are not comparable: one report refuses them, unless told
    assert main(["report", str(run), str(regraded)]) == 2
    assert "not comparable" in capsys.readouterr().err
    assert main(["report", str(run), str(regraded), "--allow-mixed", "--format", "json"]) == 0
    rates = [c["success_rate"]["mean"] for c in json.loads(capsys.readouterr().out)["configurations"]]
    assert rates == [1.0, 0.5]
    # the viewer shows what the re-grade changed
    page = Site(Catalog.open([regraded])).page("c/run-regraded/e/dentist_moves_checkup/run-1.html")
    assert page is not None
    text = page.body.decode()
    assert 'id="regraded"' in text and "goal checkup_moved: pass" in text


def test_an_episode_whose_world_changed_is_not_regraded_but_said_so(
    played: tuple[Path, Path], capsys: pytest.CaptureFixture[str]
) -> None:
    run, folder = played
    _edit(folder, "five_a_side_kickoff_moved", "Ollie Grant", "Ollie Grantham")  # the seed, not a check
    out = run.parent / "again"
    assert main(["regrade", str(run), "--scenario-path", str(folder), "-o", str(out)]) == 0
    assert "not re-graded: five_a_side_kickoff_moved run 1" in capsys.readouterr().out
    records = {record.key: record for record in load_run(out).records}
    refused = records[("five_a_side_kickoff_moved", 1)]
    assert refused.status == "failed" and refused.failure is not None
    assert refused.failure.kind == "not_regradable" and "changed since it ran" in refused.failure.message
    assert records[("dentist_moves_checkup", 2)].complete  # the other scenario is re-graded


def test_a_regrade_goes_to_its_own_folder(
    played: tuple[Path, Path], capsys: pytest.CaptureFixture[str]
) -> None:
    run, folder = played
    assert main(["regrade", str(run), "--scenario-path", str(folder), "-o", str(run)]) == 2
    assert "new folder" in capsys.readouterr().err
    busy = run.parent / "busy"
    busy.mkdir()
    (busy / "notes.txt").write_text("mine")
    assert main(["regrade", str(run), "--scenario-path", str(folder), "-o", str(busy)]) == 2
    assert "not empty" in capsys.readouterr().err
    out = run.parent / "regraded"
    for _ in range(2):  # an earlier re-grade of the same run is done again in its place
        assert main(["regrade", str(run), "--scenario-path", str(folder), "-o", str(out)]) == 0
    assert len(load_run(out).records) == 4
    assert main(["regrade", str(out), "--scenario-path", str(folder)]) == 2
    assert "itself a re-grade" in capsys.readouterr().err


def test_a_judge_model_reads_the_free_text_checks_once(
    played: tuple[Path, Path], capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setenv("OPENAI_API_KEY", "sk-pare-test")  # the judge's default key variable
    run, folder = played
    out = run.parent / "judged"
    with ChatServer(lambda body: completion("YES\nIt asks for the Thursday slot.")) as server:
        argv = ["regrade", str(run), "--scenario-path", str(folder), "-o", str(out)]
        argv += ["--judge-model", "pare-judge", "--judge-endpoint", server.base_url]
        assert main([*argv]) == 0
        asked = server.request_count
        assert asked > 0
        assert "judge pare-judge" in capsys.readouterr().out
        assert main([*argv]) == 0  # again: every answer comes from the new folder's cache
        assert server.request_count == asked
    trajectory = json.loads((out / load_run(out).records[0].trajectory).read_text())  # type: ignore[operator]
    judged = [j for goal in trajectory["outcome"]["goals"] for c in goal["checks"] for j in c["judged"]]
    assert judged and all(j["verdict"]["model"] == "pare-judge" for j in judged)
