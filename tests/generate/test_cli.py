"""``pare generate`` and ``pare scenarios review`` from the command line."""

from __future__ import annotations

import io
import json
import os
from pathlib import Path

import pytest

from pare.cli import main
from pare.generate.review import REJECTED, REVIEWS
from pare.scenarios import load_scenario
from pare.scenarios.schema import SCHEMA_FILE
from pare.testing import ChatServer, openai_reasoning
from tests.generate.conftest import ScriptedGenerator, example_answers


@pytest.fixture(autouse=True)
def wide_terminal(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("COLUMNS", "250")


def _generate(server: ChatServer, folder: Path, library: Path, *options: str) -> int:
    server.responder = ScriptedGenerator({1: {stage: [text] for stage, text in example_answers().items()}})
    return _generate_with(server, folder, library, *options)


def _generate_with(server: ChatServer, folder: Path, library: Path, *options: str) -> int:
    """``pare generate`` of one email and calendar candidate against ``server`` as it answers now."""
    return main(
        [
            "generate",
            "--apps",
            "email,calendar",
            "-n",
            "1",
            "-o",
            str(folder),
            "--endpoint",
            server.base_url,
            "--library",
            str(library),
            "--no-progress",
            *(options or ("--model", "pare-generator")),
        ]
    )


def test_generate_prints_each_candidate_and_the_cost(
    server: ChatServer, tmp_path: Path, library: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    options = ("--model", "pare-generator", "--set", "generator.max_tokens=16000")
    assert _generate(server, tmp_path / "out", library, *options) == 0
    out = capsys.readouterr().out
    assert server.requests[0]["max_tokens"] == 16000
    assert "candidate-001" in out and "passed" in out and "dentist_example" in out
    assert "model calls: 4" in out and "cost" in out
    assert f"pare scenarios review {tmp_path / 'out'}" in out.replace("\n", "")
    assert server.requests[0]["temperature"] == 0.7


def test_generate_sends_a_reasoning_model_no_temperature(
    server: ChatServer, tmp_path: Path, library: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    server.responder = openai_reasoning(
        ScriptedGenerator({1: {stage: [text] for stage, text in example_answers().items()}})
    )
    options = ("--model", "o3-mini", "--set", "generator.max_tokens=16000")
    assert _generate_with(server, tmp_path / "out", library, *options) == 0
    assert "passed" in capsys.readouterr().out
    assert server.requests and all("temperature" not in body for body in server.requests)
    assert {body["max_completion_tokens"] for body in server.requests} == {16000}


def test_generate_refuses_unknown_apps_and_a_folder_of_other_settings(
    server: ChatServer, tmp_path: Path, library: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    assert main(["generate", "--apps", "emial", "-o", str(tmp_path / "x")]) == 2
    assert "unknown app 'emial'" in capsys.readouterr().err
    assert _generate(server, tmp_path / "out", library) == 0
    code = main(
        ["generate", "--apps", "email,contacts", "-o", str(tmp_path / "out"), "--endpoint", server.base_url]
    )
    error = capsys.readouterr().err
    assert code == 2 and "generated with other settings (apps, models differ)" in error


def test_review_accepts_into_the_library_and_sets_rejected_aside(
    server: ChatServer, tmp_path: Path, library: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    folder = tmp_path / "out"
    assert _generate(server, folder, library) == 0
    second = folder / "dentist_copy.yaml"
    second.write_text(
        (folder / "dentist_example.yaml").read_text().replace("id: dentist_example", "id: dentist_copy")
    )
    capsys.readouterr()

    assert main(["scenarios", "review", str(folder), "--no-input"]) == 0
    shown = capsys.readouterr().out
    for part in (
        "story",
        "seed volume",
        "email (1 emails",
        "events",
        "oracle",
        "goals",
        "variants",
        "gate: passes",
    ):
        assert part in shown, part
    assert "variant:takes_friday" in shown and "2 candidate(s) still waiting" in shown
    # each goal shows its checks, not their number: the author's sentence, then what is looked for
    flat = " ".join(shown.split())
    assert "checks)" not in flat
    assert "- One check-up, not a second one beside the old: calendar.events: exactly 1" in flat
    assert "judged for: The email accepts the Thursday 08:00 slot" in flat

    assert main(["scenarios", "review", str(folder), "--reject", "dentist_copy"]) == 2
    assert "--reason" in capsys.readouterr().err
    target = tmp_path / "accepted"
    code = main(
        [
            "scenarios", "review", str(folder), "--library", str(target),
            "--accept", "dentist_example", "--reject", "dentist_copy", "--reason", "a copy of the other",
        ]
    )  # fmt: skip
    assert code == 0
    accepted = target / "dentist_example.yaml"
    assert load_scenario(accepted).id == "dentist_example"
    schema = Path(os.path.relpath(SCHEMA_FILE, target)).as_posix()  # the schema line follows the file
    assert accepted.read_text().startswith(f"# yaml-language-server: $schema={schema}\n")
    rejected = folder / REJECTED / "dentist_copy.yaml"
    assert rejected.read_text().startswith("# rejected: a copy of the other\n")
    assert not list(folder.glob("*.yaml"))
    decisions = [json.loads(line) for line in (folder / REVIEWS).read_text().splitlines()]
    assert [(d["scenario_id"], d["decision"]) for d in decisions] == [
        ("dentist_copy", "rejected"),
        ("dentist_example", "accepted"),
    ]


def test_review_names_unknown_candidates(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    (tmp_path / "dentist_example.yaml").write_text("id: dentist_example\n")
    assert main(["scenarios", "review", str(tmp_path), "--accept", "dentist_exampel"]) == 2
    assert "Did you mean 'dentist_example'" in capsys.readouterr().err


def test_review_asks_at_a_terminal(
    server: ChatServer,
    tmp_path: Path,
    library: Path,
    monkeypatch: pytest.MonkeyPatch,
    capsys: pytest.CaptureFixture[str],
) -> None:
    folder = tmp_path / "out"
    assert _generate(server, folder, library) == 0
    monkeypatch.setattr("sys.stdin", io.StringIO("r\nthe concert is too convenient\n"))
    assert main(["scenarios", "review", str(folder), "--interactive"]) == 0
    assert "rejected dentist_example (the concert is too convenient)" in capsys.readouterr().out
    assert (folder / REJECTED / "dentist_example.yaml").read_text().startswith("# rejected: the concert")


def test_generate_through_the_litellm_backend(
    server: ChatServer,
    tmp_path: Path,
    library: Path,
    monkeypatch: pytest.MonkeyPatch,
    capsys: pytest.CaptureFixture[str],
) -> None:
    pytest.importorskip("litellm")
    monkeypatch.setenv("PARE_TEST_GENERATOR_KEY", "sk-local")  # litellm sends no dummy key of its own
    options = (
        "--provider",
        "litellm",
        "--model",
        "openai/pare-generator",
        "--api-key-env",
        "PARE_TEST_GENERATOR_KEY",
    )
    assert _generate(server, tmp_path / "out", library, *options) == 0
    assert "1 passed" in capsys.readouterr().out
    assert {request["model"] for request in server.requests} == {"pare-generator"}


def test_the_generators_bar_is_a_batch_bar_counting_cost_like_a_runs() -> None:
    from rich.console import Console

    from pare.generate.folder import CandidateRecord
    from pare.generate.progress import RichGenerationProgress

    console = Console(record=True, width=200, force_terminal=False)
    progress = RichGenerationProgress(console)
    progress.started(6, 2)
    progress.stage("candidate-003", "seed", 2)
    priced = {"total": {"calls": 3, "known_cost_usd": 0.012, "unknown_cost_calls": 1}}
    progress.finished(CandidateRecord(slot="candidate-003", index=3, status="passed", usage=priced))
    progress.stopped()
    text = console.export_text()
    assert "resuming: 2 of 6 candidates are already finished" in text
    assert "3/6" in text and "1 passed, 0 duplicate, 0 failed" in text
    assert "cost $0.0120 + unpriced" in text
    quiet = RichGenerationProgress(Console(record=True, width=200))
    quiet.started(1, 0)
    quiet.stopped()
    assert "cost n/a" in quiet.console.export_text()  # no model called: not "$0"
