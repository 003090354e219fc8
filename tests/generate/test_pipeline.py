"""The pipeline end to end against the local chat server playing the generator from scripted answers."""

from __future__ import annotations

import json
import re
import shutil
from pathlib import Path

from pare.generate import generate, read_provenance
from pare.generate.folder import OUTCOMES, TRANSCRIPTS, transcript_hash
from pare.generate.prompts import STAGE_HEADINGS
from pare.generate.sections import STAGE_KEYS, STAGES, split_sections
from pare.scenarios import load_scenario
from pare.testing import ChatServer, failure
from tests.generate.conftest import BENCH, ScriptedGenerator, example_answers, make_config


def _script(**stages: list[str]) -> dict[str, list[str]]:
    answers = {stage: [text] for stage, text in example_answers().items()}
    answers.update(stages)
    return answers


def _outcomes(folder: Path) -> list[dict[str, object]]:
    return [json.loads(line) for line in (folder / OUTCOMES).read_text().splitlines()]


def test_a_candidate_that_passes_first_time(server: ChatServer, tmp_path: Path, library: Path) -> None:
    server.responder = generator = ScriptedGenerator({1: _script()})
    summary = generate(make_config(server, tmp_path / "out", library))

    [record] = summary.records
    assert record.status == "passed", record
    assert record.attempts == {"story": 1, "seed": 1, "events": 1, "validation": 1}
    assert server.request_count == 4 and generator.judge_calls == 0  # no library story near: no judge
    written = tmp_path / "out" / "dentist_example.yaml"
    assert load_scenario(written).id == "dentist_example"
    provenance = read_provenance(written.read_text())
    assert provenance is not None
    assert provenance["generator"]["model"] == "pare-generator"
    assert provenance["settings"]["apps"] == ["email", "calendar"]
    for stage, digest in provenance["transcripts"].items():
        kept = json.loads((tmp_path / "out" / TRANSCRIPTS / "candidate-001" / f"{stage}.json").read_text())
        assert kept["hash"] == digest == transcript_hash(kept["messages"])
    # each stage's prompt carries what it needs
    prompts = [request["messages"] for request in server.requests]
    assert "JSON Schema" in prompts[0][0]["content"] and "worked example" in prompts[0][0]["content"]
    assert "Seed format of calendar" in prompts[1][1]["content"]
    assert "email__receive_email(" in prompts[2][1]["content"] and "seed:" in prompts[2][1]["content"]
    assert "oracle:" in prompts[3][1]["content"]
    # cost is recorded per candidate and for the session (prices given: 1000 in, 500 out per call)
    assert record.usage["total"]["calls"] == 4
    assert summary.usage["total"]["known_cost_usd"] == 4 * (1000 * 1.0 + 500 * 2.0) / 1e6


def test_a_gate_breach_goes_back_and_is_repaired(server: ChatServer, tmp_path: Path, library: Path) -> None:
    good = example_answers()
    broken_seed = good["seed"].replace("subject: Roadmap review", "subjct: Roadmap review")
    # the near-miss does what the oracle does: it passes, so the gate says its declaration is wrong
    wrong_variant = (
        good["validation"]
        .replace(
            "{start_datetime: day+4 17:30, end_datetime: day+4 18:15}}}",
            "{start_datetime: day+3 08:00, end_datetime: day+3 08:45}}}",
        )
        .replace("content: Friday at 17:30 works for me.", "content: Thursday at 08:00 works for me.")
    )
    # the oracle moves the check-up to end before it starts: the calendar refuses the call when played
    failing_call = good["events"].replace("end_datetime: day+3 08:45}", "end_datetime: day+3 07:45}", 1)
    assert (
        wrong_variant != good["validation"] and broken_seed != good["seed"] and failing_call != good["events"]
    )
    server.responder = ScriptedGenerator(
        {
            1: _script(
                seed=[broken_seed, good["seed"]],
                events=[failing_call, good["events"]],
                validation=[wrong_variant, good["validation"]],
            )
        }
    )
    summary = generate(make_config(server, tmp_path / "out", library))

    [record] = summary.records
    assert record.status == "passed", record
    assert record.attempts == {"story": 1, "seed": 2, "events": 2, "validation": 2}
    feedback = {
        request["messages"][-1]["content"] for request in server.requests if len(request["messages"]) > 3
    }
    seed_feedback = next(text for text in feedback if "seed stage" in text)
    assert "seed.email.emails[0].subjct: unknown field" in seed_feedback
    assert "candidate.yaml" not in seed_feedback  # the joined file's line numbers mean nothing to the model
    [marked] = [line for line in seed_feedback.splitlines() if line.lstrip().startswith("> |")]
    assert "subjct: Roadmap review" in marked  # the offending line, quoted
    played = next(text for text in feedback if "events stage" in text)
    assert "[oracle] assistant call #6 calendar.edit_calendar_event failed: The event would end" in played
    gate_feedback = next(text for text in feedback if "validation stage" in text)
    assert "[variant:takes_friday]" in gate_feedback and "played" in gate_feedback
    # the slack rule can be kept only knowing the turns: the played stages say them
    assert re.search(r"Turns taken, of the 10 an episode has: the oracle \d+, the slow user", played)
    validation_prompt = next(
        request["messages"][1]["content"]
        for request in server.requests
        if request["messages"][1]["content"].startswith(STAGE_HEADINGS["validation"])
    )
    assert re.search(r"the oracle \d+, the slow user \(.*\) \d+", validation_prompt)


def test_a_retold_library_story_is_dropped_with_the_judges_reason(
    server: ChatServer, tmp_path: Path, library: Path
) -> None:
    shutil.copy(BENCH / "dentist_moves_checkup.yaml", library)
    verdict = '{"duplicate": true, "same_as": "dentist_moves_checkup", "reason": "the same moved check-up"}'
    server.responder = generator = ScriptedGenerator({1: _script()}, verdicts=[verdict])
    summary = generate(make_config(server, tmp_path / "out", library))

    [record] = summary.records
    assert record.status == "duplicate" and record.stage == "story"
    assert "dentist_moves_checkup" in record.reason and "the same moved check-up" in record.reason
    assert generator.judge_calls == 1 and server.request_count == 2  # the story, then the judge: no more
    judged = server.requests[1]["messages"][0]["content"]
    assert "The dentist moves tomorrow's check-up" in judged  # the nearest library story was shown
    assert not list((tmp_path / "out").glob("*.yaml"))
    assert _outcomes(tmp_path / "out")[0]["status"] == "duplicate"


def test_the_whole_measure_catches_a_retelling_the_judge_let_through(
    server: ChatServer, tmp_path: Path, library: Path
) -> None:
    shutil.copy(BENCH / "dentist_moves_checkup.yaml", library)
    server.responder = generator = ScriptedGenerator({1: _script()})  # the judge says: new
    [record] = generate(make_config(server, tmp_path / "out", library)).records
    assert generator.judge_calls == 1 and record.attempts["judge"] == 1
    assert record.status == "duplicate" and record.stage == "validation"
    assert "pare scenarios similar scores it" in record.reason and "dentist_moves_checkup" in record.reason
    assert not list((tmp_path / "out").glob("*.yaml"))


def test_a_candidate_out_of_retries_is_reported(server: ChatServer, tmp_path: Path, library: Path) -> None:
    broken = example_answers()["seed"].replace("subject: Roadmap review", "subjct: Roadmap review")
    server.responder = ScriptedGenerator({1: _script(seed=[broken])})
    summary = generate(make_config(server, tmp_path / "out", library, stage_retries=2))

    [record] = summary.records
    assert record.status == "failed" and record.stage == "seed"
    assert record.attempts["seed"] == 3 and server.request_count == 1 + 3
    assert any("subjct" in problem for problem in record.problems)
    assert not list((tmp_path / "out").glob("*.yaml"))
    kept = json.loads((tmp_path / "out" / TRANSCRIPTS / "candidate-001" / "seed.json").read_text())
    assert kept["problems"] == record.problems


def test_a_stage_may_write_only_its_own_sections(server: ChatServer, tmp_path: Path, library: Path) -> None:
    good = example_answers()
    both = good["seed"].replace("```yaml\n", "```yaml\ngoals: []\n", 1)
    server.responder = ScriptedGenerator({1: _script(seed=[both, good["seed"]])})
    [record] = generate(make_config(server, tmp_path / "out", library)).records
    assert record.status == "passed" and record.attempts["seed"] == 2
    assert "'goals' cannot be written here" in server.requests[2]["messages"][-1]["content"]


def _library_answers(scenario_id: str) -> dict[str, list[str]]:
    """A library scenario cut into the four stages' answers."""
    text = (BENCH / f"{scenario_id}.yaml").read_text()
    sections = split_sections(text, [key for stage in STAGES for key in STAGE_KEYS[stage]]).sections
    return {
        stage: ["```yaml\n" + "".join(sections[key] for key in STAGE_KEYS[stage] if key in sections) + "```"]
        for stage in STAGES
    }


def test_output_resumes_and_runs_candidates_concurrently(
    server: ChatServer, tmp_path: Path, library: Path
) -> None:
    server.responder = ScriptedGenerator(
        {1: _script(), 2: _library_answers("plumber_asks_which_mornings_free_next_week"), 3: _script()}
    )
    folder = tmp_path / "out"
    first = generate(make_config(server, folder, library, count=1))
    assert [record.status for record in first.records] == ["passed"]
    requests = server.request_count

    again = generate(make_config(server, folder, library, count=1))
    assert again.records == [] and again.skipped == 1 and server.request_count == requests

    server.delay_s = 0.05
    more = generate(make_config(server, folder, library, count=3, concurrency=2))
    assert server.max_in_flight == 2
    outcomes = {r.slot: (r.status, r.scenario_id) for r in more.records}
    assert outcomes["candidate-002"] == ("passed", "plumber_asks_which_mornings_free_next_week")
    # the third retells the first, already in the folder: its id is taken, so the story goes back
    assert outcomes["candidate-003"][0] == "failed"
    assert "is taken" in " ".join(next(r for r in more.records if r.index == 3).problems)
    assert sorted(path.stem for path in folder.glob("*.yaml")) == [
        "dentist_example",
        "plumber_asks_which_mornings_free_next_week",
    ]


def test_a_provider_that_stays_down_leaves_the_candidate_to_resume(
    server: ChatServer, tmp_path: Path, library: Path
) -> None:
    server.responder = lambda body: failure(503, "overloaded")
    down = generate(make_config(server, tmp_path / "out", library))
    assert down.records == [] and "candidate-001" in down.unfinished
    assert not (tmp_path / "out" / OUTCOMES).exists()

    server.responder = ScriptedGenerator({1: _script()})
    again = generate(make_config(server, tmp_path / "out", library))
    assert [record.status for record in again.records] == ["passed"] and not again.unfinished


def test_an_unreadable_verdict_goes_back_to_the_judge_once(
    server: ChatServer, tmp_path: Path, library: Path
) -> None:
    shutil.copy(BENCH / "dentist_moves_checkup.yaml", library)
    server.responder = generator = ScriptedGenerator({1: _script()}, verdicts=["Looks new to me."])
    [record] = generate(make_config(server, tmp_path / "out", library)).records
    assert generator.judge_calls == 2
    assert record.status == "failed" and record.stage == "story"
    assert "judge" in record.reason and "no JSON object" in record.reason
