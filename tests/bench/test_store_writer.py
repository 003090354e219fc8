"""The run store's writer: a line only after its trajectory, finished only once stored, errors, both modes."""

from __future__ import annotations

import io
from pathlib import Path
from typing import Any

import pytest

import pare.bench._store_writer as writer_module
import pare.bench.store as store_module
from pare.bench.runconfig import build_config
from pare.bench.runner import run_benchmark
from pare.cli import main
from pare.errors import UserInputError
from pare.results.records import EpisodeRecord
from pare.results.run_folder import EPISODES, load_run, read_records
from pare.results.trajectory import read_trajectory
from pare.scenarios import library

SMOKE = ["dentist_moves_checkup", "five_a_side_kickoff_moved", "dad_printer_ink_from_note"]


def _config(output: Path, **extra: Any) -> Any:
    return build_config({"scenarios": {"ids": SMOKE}, "runs": 3, "output": str(output), **extra})


def _keys_in(file: Path) -> list[tuple[str, int]]:
    return [record.key for record in read_records(file)] if file.exists() else []


@pytest.fixture(params=["process", "inline"])
def writer_mode(request: pytest.FixtureRequest, monkeypatch: pytest.MonkeyPatch) -> str:
    """Both writers: the writer process, and storing in the run's thread (where there are no pipes)."""
    monkeypatch.setattr(store_module, "WRITER_PROCESS", request.param == "process")
    return str(request.param)


class CheckingProgress:
    """A progress sink that checks, as each episode is reported, that its line and trajectory are stored;
    it can block an episode's trajectory folder (a file in its place) when the run starts.
    """

    def __init__(self, folder: Path, block: str | None = None) -> None:
        self.folder = folder
        self.block = block
        self.reported: list[EpisodeRecord] = []

    def started(self, total: int, done: int, label: str) -> None:
        if self.block is not None:
            (self.folder / "trajectories").mkdir(exist_ok=True)
            (self.folder / "trajectories" / self.block).write_text("not a folder")

    def finished(self, record: EpisodeRecord) -> None:
        assert record.key in _keys_in(self.folder / EPISODES), "reported before its line was written"
        assert read_trajectory(self.folder / str(record.trajectory)).run == record.run
        self.reported.append(record)

    def stopped(self) -> None:
        pass


def test_an_episode_is_finished_once_its_line_is_written(tmp_path: Path, writer_mode: str) -> None:
    folder = tmp_path / "run"
    progress = CheckingProgress(folder)
    summary = run_benchmark(_config(folder), progress=progress)
    assert summary.complete == 9
    stored = _keys_in(folder / EPISODES)
    assert [r.key for r in progress.reported] == stored == [r.key for r in summary.records]
    assert not list(folder.rglob("*.tmp"))


def test_a_stored_episode_is_reported_while_the_next_one_still_plays(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, writer_mode: str
) -> None:
    import asyncio

    import pare.bench.runner as runner_module

    folder = tmp_path / "run"
    progress = CheckingProgress(folder)
    real = runner_module.play_episode
    seen_while_playing: list[int] = []

    async def slow_second(plan: Any, config: Any, models: Any, attempt: int = 1) -> Any:
        if plan.run == 2:  # a long model-backed episode: the first one's report must not wait for it
            for _ in range(500):
                if progress.reported:
                    break
                await asyncio.sleep(0.01)
            seen_while_playing.append(len(progress.reported))
        return await real(plan, config, models, attempt)

    monkeypatch.setattr(runner_module, "play_episode", slow_second)
    config = build_config(
        {"scenarios": {"ids": SMOKE[:1]}, "runs": 2, "concurrency": 1, "output": str(folder)}
    )
    run_benchmark(config, progress=progress)
    assert seen_while_playing == [1] and len(progress.reported) == 2


def test_an_error_in_the_writer_stops_the_run_with_its_message_and_a_resume_completes_it(
    tmp_path: Path, writer_mode: str
) -> None:
    folder = tmp_path / "run"
    progress = CheckingProgress(folder, block="five_a_side_kickoff_moved")
    with pytest.raises(UserInputError, match=r"cannot write the run: .*five_a_side_kickoff_moved") as caught:
        run_benchmark(_config(folder), progress=progress)
    assert "run the same command again to resume" in str(caught.value)
    stored = read_records(folder / EPISODES)
    assert len(stored) < 9 and all(r.scenario_id != "five_a_side_kickoff_moved" for r in stored)
    for record in stored:  # each line names a whole trajectory
        assert read_trajectory(folder / str(record.trajectory)).run == record.run
    reported = [r.key for r in progress.reported]  # what was reported finished is stored
    assert reported == [r.key for r in stored][: len(reported)]

    (folder / "trajectories" / "five_a_side_kickoff_moved").unlink()  # fixed: the same command resumes
    resumed = run_benchmark(_config(folder))
    assert (resumed.skipped, resumed.complete) == (len(stored), 9 - len(stored))
    assert len(load_run(folder).records) == 9


def test_the_command_line_reports_a_writer_error_cleanly(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    import pare.cli.run_cmd as run_cmd

    folder = tmp_path / "run"
    monkeypatch.setattr(run_cmd, "progress_sink", lambda show: CheckingProgress(folder, block=SMOKE[0]))
    assert main(["run", "-s", SMOKE[0], "--runs", "2", "--no-progress", "-o", str(folder)]) == 2
    err = capsys.readouterr().err
    assert "error:" in err and "cannot write the run" in err and SMOKE[0] in err and "Traceback" not in err
    assert read_records(folder / EPISODES) == []


def test_a_store_hands_back_what_it_wrote_and_refuses_appends_once_closed(
    tmp_path: Path, writer_mode: str
) -> None:
    config = _config(tmp_path / "run")
    scenarios = {scenario_id: library()[scenario_id] for scenario_id in SMOKE}
    record = EpisodeRecord(scenario_id=SMOKE[0], run=1, status="complete", scenario_hash="h", seed=0)
    with store_module.RunStore.open(tmp_path / "run", config, scenarios) as store:
        store.append(record)
        store.flush()
        assert store.committed() == [record]
        store.append(record.model_copy(update={"run": 2}))
    assert [r.run for r in store.committed()] == [2]  # stored while closing: still handed back
    assert store.done((SMOKE[0], 2))
    with pytest.raises(RuntimeError, match="closed"):
        store.append(record)
    assert _keys_in(tmp_path / "run" / EPISODES) == [(SMOKE[0], 1), (SMOKE[0], 2)]


def test_a_writer_process_that_dies_stops_the_run_with_a_clear_error(tmp_path: Path) -> None:
    config = _config(tmp_path / "run")
    scenarios = {scenario_id: library()[scenario_id] for scenario_id in SMOKE}
    record = EpisodeRecord(scenario_id=SMOKE[0], run=1, status="complete", scenario_hash="h", seed=0)
    store = store_module.RunStore.open(tmp_path / "run", config, scenarios)
    try:
        assert isinstance(store._writer, store_module._WriterProcess)
        store._writer._process.kill()
        store._writer._process.wait()
        with pytest.raises(RuntimeError, match="writer process ended unexpectedly"):
            for _ in range(100):  # the pipe takes a frame or two before it is known to be broken
                store.append(record)
                store.flush()
    finally:
        store.close()


# -- the writer's protocol, in this process ---------------------------------------------------------------
def test_the_writer_stores_each_trajectory_before_its_line_and_answers_after_it(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    events: list[str] = []
    real = writer_module.write_atomically

    def recording(path: str, data: bytes, made: Any = None) -> None:
        events.append(f"trajectory {Path(path).name} (lines: {_lines(tmp_path)})")
        real(path, data, made)

    class Replies(io.BytesIO):
        def flush(self) -> None:
            events.append(f"reply (lines: {_lines(tmp_path)})")

    monkeypatch.setattr(writer_module, "write_atomically", recording)
    frames = b"".join(
        writer_module.frame(f"trajectories/s/run-{run}.json", b"{}\n", f'{{"run":{run}}}\n'.encode())
        for run in (1, 2)
    ) + writer_module.frame(None, b"", b'{"failed":true}\n')
    replies = Replies()
    assert writer_module.serve(str(tmp_path), io.BytesIO(frames), replies) == 0
    assert replies.getvalue() == b"..."
    assert events == [
        "trajectory run-1.json (lines: 0)",
        "reply (lines: 1)",
        "trajectory run-2.json (lines: 1)",
        "reply (lines: 2)",
        "reply (lines: 3)",
    ]
    assert (tmp_path / "trajectories" / "s" / "run-2.json").read_bytes() == b"{}\n"


def test_the_writer_drops_a_frame_cut_short_and_stops_at_the_first_error(tmp_path: Path) -> None:
    whole = writer_module.frame("trajectories/s/run-1.json", b"{}\n", b"{}\n")
    cut = writer_module.frame("trajectories/s/run-2.json", b"{}\n", b"{}\n")[:-2]
    replies = io.BytesIO()
    assert writer_module.serve(str(tmp_path), io.BytesIO(whole + cut), replies) == 0  # killed mid-send
    assert replies.getvalue() == b"." and _lines(tmp_path) == 1

    (tmp_path / "trajectories" / "t").write_text("a file where a folder should be")
    blocked = writer_module.frame("trajectories/t/run-1.json", b"{}\n", b"{}\n")
    replies = io.BytesIO()
    assert writer_module.serve(str(tmp_path), io.BytesIO(blocked + whole), replies) == 1
    reply = replies.getvalue()
    assert reply.startswith(b"!") and reply.endswith(b"\n") and b"trajectories/t" in reply
    assert _lines(tmp_path) == 1  # nothing after the error


def _lines(folder: Path) -> int:
    file = folder / EPISODES
    return file.read_bytes().count(b"\n") if file.exists() else 0
