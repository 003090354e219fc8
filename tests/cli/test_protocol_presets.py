"""`pare run --protocol paper` through a local chat server with scripted answers, and `pare report`'s
heading and refusal to compare runs of different protocols or scenario versions.
"""

from __future__ import annotations

import json
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import pytest

from pare.cli import main
from pare.results.run_folder import EPISODES, MANIFEST
from pare.testing import ChatServer, Reply, completion, conversation_role, proactive_play

KEY_VARIABLE = "PARE_PROTOCOL_TEST_KEY"
MALFORMED = "I will look around first."
"""The user's first answer in every episode: no action in it, so it is a format error."""


@pytest.fixture(autouse=True)
def wide(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("COLUMNS", "200")
    monkeypatch.setenv(KEY_VARIABLE, "any")


def _malformed_first(body: Mapping[str, Any]) -> bool:
    """The user's first request of an episode: its system prompt and one observation."""
    messages = body["messages"]
    return conversation_role(messages) == "user" and len(messages) == 2


def scripted() -> Any:
    """proactive_play, except that the user's first answer of each episode is malformed."""
    play = proactive_play()

    def respond(body: dict[str, Any]) -> Reply:
        return completion(MALFORMED) if _malformed_first(body) else play(body)

    return respond


def model_run(output: Path, server: ChatServer, *extra: str) -> list[str]:
    argv = ["run", "--split", "smoke", "--runs", "1", "--no-progress", "--cache", "off", "-o", str(output)]
    argv += ["--user-model", "test-user", "--user-endpoint", server.base_url]
    argv += ["--assistant-model", "test-assistant", "--assistant-endpoint", server.base_url]
    for role in ("user", "assistant"):
        argv += ["--set", f"models.{role}.api_key_env={KEY_VARIABLE}"]
    return argv + list(extra)


def _records(folder: Path) -> list[dict[str, Any]]:
    return [json.loads(line) for line in (folder / EPISODES).read_text().splitlines()]


def _user_steps(folder: Path) -> int:
    steps = 0
    for record in _records(folder):
        trajectory = json.loads((folder / record["trajectory"]).read_text())
        steps += sum(step["actor"] == "user" for step in trajectory["steps"])
    return steps


def test_a_paper_protocol_run_of_the_smoke_split_plays_and_records_the_papers_protocol(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    with ChatServer(scripted()) as server:
        assert main(model_run(tmp_path / "paper", server, "--protocol", "paper")) == 0
        paper_requests = server.requests
        server.reset()
        assert main(model_run(tmp_path / "pare", server)) == 0
        pare_requests = server.requests
    paper = tmp_path / "paper"

    manifest = json.loads((paper / MANIFEST).read_text())
    assert manifest["protocol"]["preset"] == "paper" and manifest["protocol"]["overrides"] == {}
    assert manifest["protocol"]["settings"]["proposal_ttl_turns"] is None
    assert manifest["identity"]["protocol"]["preset"] == "paper"
    assert json.loads((tmp_path / "pare" / MANIFEST).read_text())["protocol"]["preset"] == "pare"
    records = _records(paper)
    assert len(records) == 5 and all(record["status"] == "complete" for record in records)

    # the user is told the appendix's words, and nothing of a proposal's lifetime
    user_prompts = {
        r["messages"][0]["content"] for r in paper_requests if conversation_role(r["messages"]) == "user"
    }
    assert user_prompts
    for prompt in user_prompts:
        flat = " ".join(prompt.split())
        assert flat.count("You have to be EXTREMELY STRICT about accepting proposals.") == 2
        assert "If you are not sure, simply reject the proposal." in flat
        assert "Be a demanding user" not in flat and "withdrawn" not in flat
    pare_user = [
        r["messages"][0]["content"] for r in pare_requests if conversation_role(r["messages"]) == "user"
    ]
    assert all("Be a demanding user" in prompt and "EXTREMELY STRICT" not in prompt for prompt in pare_user)

    # a malformed answer costs the paper's user a step; PARE's user is asked again within the step
    paper_calls = sum(conversation_role(r["messages"]) == "user" for r in paper_requests)
    pare_calls = sum(conversation_role(r["messages"]) == "user" for r in pare_requests)
    assert paper_calls == _user_steps(paper)
    assert pare_calls == _user_steps(tmp_path / "pare") + len(records)
    assert all(proposal["resolution"] != "expired" for record in records for proposal in record["proposals"])

    capsys.readouterr()
    assert main(["report", str(paper), "--format", "markdown", "--section", "main"]) == 0
    assert capsys.readouterr().out.startswith("Protocol: paper\n")


def _oracle(folder: Path, *extra: str) -> Path:
    argv = ["run", "--no-progress", "--runs", "1", "-s", "dentist_moves_checkup", "-o", str(folder)]
    assert main([*argv, *extra]) == 0
    return folder


def test_report_refuses_runs_of_different_presets_unless_told_and_names_each_protocol(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    pare = _oracle(tmp_path / "pare")
    paper = _oracle(tmp_path / "paper", "--protocol", "paper", "--max-turns", "12")
    capsys.readouterr()
    assert main(["report", str(pare), str(paper)]) == 2
    err = capsys.readouterr().err
    assert "not comparable" in err and "different protocol presets" in err and "--allow-mixed" in err

    assert main(["report", str(pare), str(paper), "--allow-mixed", "--format", "markdown"]) == 0
    captured = capsys.readouterr()
    assert "warning: not comparable" in captured.err
    heading = captured.out.splitlines()[0]
    assert heading.startswith("Protocols: ") and "pare" in heading and "paper (max_turns=12)" in heading

    assert main(["report", str(paper), "--format", "csv"]) == 0
    assert "paper (max_turns=12)" in capsys.readouterr().out
    assert main(["report", str(paper), "--format", "json"]) == 0
    [configuration] = json.loads(capsys.readouterr().out)["configurations"]
    assert configuration["protocol"] == "paper" and configuration["protocol_overrides"] == {"max_turns": 12}
    assert main(["report", str(paper), "--format", "latex", "--section", "main"]) == 0
    assert "Protocol: paper (max\\_turns=12)." in capsys.readouterr().out


def test_report_refuses_runs_that_played_different_versions_of_a_scenario(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    first = _oracle(tmp_path / "first")
    second = _oracle(tmp_path / "second", "--seed", "1")
    manifest = json.loads((second / MANIFEST).read_text())
    manifest["plan"]["scenarios"]["dentist_moves_checkup"] = "0" * 16  # as if the scenario had been edited
    (second / MANIFEST).write_text(json.dumps(manifest))
    capsys.readouterr()
    assert main(["report", str(first), str(second)]) == 2
    err = capsys.readouterr().err
    assert "scenario(s) differ between the runs" in err and "dentist_moves_checkup" in err
    # the same runs without the edit share a report
    assert main(["report", str(first), str(_oracle(tmp_path / "third", "--seed", "2"))]) == 0
