"""A scenario id names files, so it is bounded where scenarios are read: an id too long for a file name is
a validation error that names the limit (sent back to the generator like any other problem), never an
``OSError`` when the candidate is written, on this and every later session.
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from pare.cli import main
from pare.generate.folder import OUTCOMES, GenerationFolder
from pare.scenarios.loader import ScenarioError, load_scenario, parse_scenario
from pare.scenarios.model import MAX_SCENARIO_ID_LENGTH
from pare.testing import ChatServer
from tests.generate.conftest import (
    ScriptedGenerator,
    example_answers,
    example_text,
    library,
    make_config,
    server,
)

__all__ = ["library", "server"]

LIMIT = f"at most {MAX_SCENARIO_ID_LENGTH} characters"


def test_an_id_past_the_limit_is_refused_with_the_limit() -> None:
    text = example_text().replace("id: dentist_example", "id: " + "a" * (MAX_SCENARIO_ID_LENGTH + 1))
    with pytest.raises(ScenarioError, match=LIMIT) as refused:
        parse_scenario(text, source="long.yaml")
    assert "long.yaml:1: id:" in str(refused.value)


def test_an_id_at_the_limit_loads_from_its_file(tmp_path: Path) -> None:
    scenario_id = "a" * MAX_SCENARIO_ID_LENGTH
    path = tmp_path / f"{scenario_id}.yaml"
    path.write_text(example_text().replace("id: dentist_example", f"id: {scenario_id}"), encoding="utf-8")
    assert load_scenario(path).id == scenario_id


def test_a_candidate_is_written_whatever_room_its_name_leaves(
    tmp_path: Path, library: Path, server: ChatServer
) -> None:
    # A name at the file system's limit (255 bytes) leaves no room for a temporary file's suffix.
    folder = GenerationFolder.open(make_config(server, tmp_path / "out", library))
    longest = "a" * (255 - len(".yaml"))
    name = folder.write_candidate(longest, "id: x\n", {"slot": "candidate-001"})
    assert (folder.path / name).read_text(encoding="utf-8").endswith("id: x\n")
    assert sorted(path.name for path in folder.path.iterdir()) == sorted(["manifest.json", name])


def test_a_generator_that_writes_a_long_id_is_told_the_limit_and_every_session_ends_cleanly(
    tmp_path: Path, library: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    answers = example_answers()
    long_id = "dentist_" + "x" * 242  # 250 characters: the audit's id
    story = answers["story"].replace("id: dentist_example", f"id: {long_id}")
    assert long_id in story
    scripts = {1: {**{stage: [text] for stage, text in answers.items()}, "story": [story, story]}}
    folder = tmp_path / "out"
    argv = ["generate", "--apps", "email,calendar", "-n", "1", "-o", str(folder), "--no-progress"]
    argv += ["--library", str(library), "--model", "pare-generator", "--retries", "1"]
    with ChatServer(ScriptedGenerator(scripts)) as chat:
        for _session in range(2):
            assert main([*argv, "--endpoint", chat.base_url]) == 0
            assert "Traceback" not in capsys.readouterr().err
        retried = [body for body in chat.requests if any(LIMIT in str(m) for m in body["messages"])]
    assert retried, "the problem was not sent back to the generator"
    outcome = json.loads((folder / OUTCOMES).read_text(encoding="utf-8"))
    assert outcome["status"] == "failed" and outcome["stage"] == "story"
    assert any(LIMIT in problem for problem in outcome["problems"])
