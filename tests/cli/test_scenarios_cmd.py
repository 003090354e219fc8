from __future__ import annotations

import io
import json
from pathlib import Path
from typing import Any

import pytest

from pare.cli import main
from pare.scenarios import library
from pare.scenarios.library import BENCH_DIR, scenario_files
from tests.scenarios.helpers import base, fair, sound, to_yaml


@pytest.fixture
def wide_console(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("COLUMNS", "200")


def _write(folder: Path, data: dict[str, object]) -> Path:
    path = folder / f"{data['id']}.yaml"
    path.write_text(to_yaml(data))
    return path


def test_check_passes_a_sound_scenario(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], wide_console: None
) -> None:
    _write(tmp_path, sound())
    assert main(["scenarios", "check", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert "tiny_reply" in out and "all 1 scenarios pass the gate" in out
    assert "busy user" in out
    assert main(["scenarios", "check", "-v", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert "variant:declines" in out and "Saying Thursday does not work is not a yes." in out
    assert "[variant:wrong_person] NO replied:" in out


def test_check_counts_held_out_probes_and_fails_on_a_misjudged_one(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], wide_console: None
) -> None:
    data = sound()
    right = [{**data["variants"][0], "id": "probe_right", "held_out": True}]
    probe = {**data["variants"][0], "id": "probe_misjudged", "held_out": True}
    probe["expect"] = "pass" if probe["expect"] == "fail" else "fail"
    probe.pop("fails", None)
    data["variants"] = [*data["variants"], *right, probe]
    _write(tmp_path, data)
    assert main(["scenarios", "check", str(tmp_path)]) == 1
    out = capsys.readouterr().out
    kind = "correct rejected" if probe["expect"] == "pass" else "wrong accepted"
    assert "held-out probes: 2 judged, 1 misjudged (50 %)" in out and f"1 {kind}" in out


def test_check_fails_a_scenario_whose_checks_prove_nothing(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], wide_console: None
) -> None:
    weak = sound()
    weak["id"] = "weak_checks"
    weak["goals"][0]["checks"] = [{"action": {"tool": "agent_ui__send_message_to_user"}}]  # any proposal
    _write(tmp_path, weak)
    assert main(["scenarios", "check", str(tmp_path / "weak_checks.yaml")]) == 1
    out = capsys.readouterr().out
    assert "weak_checks [unrelated]: should fail but did not" in out
    assert "weak_checks [variant:declines]: goal 'replied' should fail" in out


def test_check_reports_a_broken_oracle(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], wide_console: None
) -> None:
    broken = sound()
    broken["id"] = "late_oracle"
    broken["oracle"]["interventions"][0]["when"] = {
        "event": "ann_asks",
        "action": {"actor": "user", "tool": "email__reply"},
    }
    _write(tmp_path, broken)
    assert main(["scenarios", "check", str(tmp_path)]) == 1
    assert "late_oracle [oracle]: the assistant never proposed" in capsys.readouterr().out


def test_check_refuses_a_broken_file_with_exit_2(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    data = base()
    data["apps"] = ["emial", "calendar"]
    _write(tmp_path, data)
    assert main(["scenarios", "check", str(tmp_path)]) == 2
    err = capsys.readouterr().err
    assert "tiny_reply.yaml:" in err and "did you mean 'email'" in err.lower()


def test_list_filters(capsys: pytest.CaptureFixture[str], wide_console: None) -> None:
    assert main(["scenarios", "list", "--app", "email"]) == 0
    out = capsys.readouterr().out
    with_email = [s.id for s in library().values() if "email" in s.apps]
    assert f"{len(with_email)} scenarios" in out and with_email[0] in out
    assert (
        main(
            ["scenarios", "list", "--split", "smoke", "--difficulty", "easy", "--tag", "context_observation"]
        )
        == 0
    )
    assert main(["scenarios", "list", "--split", "smok"]) == 2
    assert "did you mean 'smoke'" in capsys.readouterr().err.lower()


def test_show_by_id_and_by_path(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], wide_console: None
) -> None:
    assert main(["scenarios", "show", "dentist_moves_checkup"]) == 0
    out = capsys.readouterr().out
    assert "Thursday" in out and "calendar__edit_calendar_event" in out and "checkup_moved" in out
    path = _write(tmp_path, base())
    assert main(["scenarios", "show", str(path)]) == 0
    out = capsys.readouterr().out
    assert "tiny_reply" in out
    # each goal shows what its checks look for, as review does, not their number
    flat = " ".join(out.split())
    assert "checks)" not in flat
    assert "- at least 1 assistant email__reply_to_email(email_id: equals 'e_ann', content: contains" in flat
    assert main(["scenarios", "show", "dentist_moves"]) == 2
    assert "did you mean 'dentist_moves_checkup'" in capsys.readouterr().err.lower()


def test_schema(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["scenarios", "schema"]) == 0
    schema = json.loads(capsys.readouterr().out)
    assert schema["title"] == "Scenario" and "oracle" in schema["required"]
    target = tmp_path / "scenario.schema.json"
    assert main(["scenarios", "schema", "-o", str(target)]) == 0
    assert json.loads(target.read_text()) == schema


def test_check_the_whole_library(capsys: pytest.CaptureFixture[str], wide_console: None) -> None:
    assert main(["scenarios", "check"]) == 0
    assert f"all {len(library())} scenarios pass the gate" in capsys.readouterr().out


def test_stats_counts_the_library_and_names_the_gaps(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], wide_console: None
) -> None:
    _write(tmp_path, fair())
    assert main(["scenarios", "stats", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert "scenarios: 1\n" in out
    assert "apps (share of scenarios using each): email 1 (100%), calendar 1 (100%)" in out
    assert "kind: proposal 1 (100%), no_proposal 0 (0%)" in out
    assert "text goals: 1, of which judged by a model: 0 (0%)" in out
    assert "variants: 1 passing, 2 failing" in out
    assert "  - library: 1 scenarios, 149 short of 150" in out
    assert "  - judge checks: 0 of 1 text goals (0%); 1 more to reach 20%" in out
    assert "  - tag goal_inference: on 0 scenarios, 30 short of 30" in out


def test_similar_finds_a_story_told_again_with_names_changed(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], wide_console: None
) -> None:
    original = sound()
    original["story"] = (
        "Ann emails Sam to ask whether Thursday works for the quarterly planning workshop in Leeds; the "
        "assistant should reply that it does, after checking the calendar."
    )
    _write(tmp_path, original)
    other = base()
    other["id"] = "lunch_with_bob"
    other["story"] = "Bob wonders about a Friday lunch at the noodle bar near the office."
    _write(tmp_path, other)
    assert main(["scenarios", "similar", str(tmp_path), "--against", "themselves"]) == 0
    assert "no pair reaches 0.60" in capsys.readouterr().out
    renamed = sound()
    renamed["id"] = "tiny_reply_again"
    renamed["story"] = original["story"].replace("Ann", "Joan").replace("Sam", "Kim").replace("Leeds", "York")
    _write(tmp_path, renamed)
    assert main(["scenarios", "similar", str(tmp_path), "--against", "themselves"]) == 1
    out = capsys.readouterr().out
    assert "1 pair(s) tell the same story:" in out and "tiny_reply ~ tiny_reply_again (0.9" in out


def test_similar_compares_a_new_file_with_the_library(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], wide_console: None
) -> None:
    """A library story told again with names changed, in a file of its own: found without naming the
    library; --against themselves leaves the library out."""
    source = BENCH_DIR / "dentist_moves_checkup.yaml"
    retold = source.read_text(encoding="utf-8").replace("Haddad", "Morel").replace("Sam", "Kim")
    retold = retold.replace("id: dentist_moves_checkup", "id: dentist_retold")
    (tmp_path / "dentist_retold.yaml").write_text(retold, encoding="utf-8")
    assert main(["scenarios", "similar", str(tmp_path / "dentist_retold.yaml")]) == 1
    out = capsys.readouterr().out
    count = len(scenario_files())
    assert f"most alike of {count} pairs (1 given against the library's {count} scenarios" in out
    assert "dentist_retold ~ dentist_moves_checkup (0.9" in out
    assert main(["scenarios", "similar", str(tmp_path), "--against", "themselves"]) == 0
    assert "most alike of 0 pairs (1 scenarios" in capsys.readouterr().out


def test_similar_given_library_files_compares_them_with_each_other(
    capsys: pytest.CaptureFixture[str], wide_console: None
) -> None:
    files = [str(BENCH_DIR / f"{name}.yaml") for name in ("dentist_moves_checkup", "sister_gift_jacket_size")]
    assert main(["scenarios", "similar", *files]) == 0
    assert "most alike of 1 pairs (2 scenarios" in capsys.readouterr().out


def test_the_similar_help_states_the_library_threshold(capsys: pytest.CaptureFixture[str]) -> None:
    from pare.scenarios.similarity import THRESHOLD

    assert main(["scenarios", "similar", "--help"]) == 0
    assert f"threshold, {THRESHOLD:.2f})" in " ".join(capsys.readouterr().out.split())


def test_match_passes_and_shows_how_the_text_was_read(capsys: pytest.CaptureFixture[str]) -> None:
    code = main(["scenarios", "match", "{affirms: [move*]}", "not Fri 🙈 Any chance we could move it?"])
    out = capsys.readouterr().out
    assert code == 0
    assert "1. \"not Fri\"  negated by 'not'" in out
    assert '2. "Any chance we could move it"' in out
    assert "negations: 'not' in clause 1" in out
    assert out.rstrip().endswith("PASS")


def test_match_fails_with_the_reason(capsys: pytest.CaptureFixture[str]) -> None:
    rule = '{"any_of": [{"affirms": ["move*"]}, {"mentions_day": "day+3"}]}'  # JSON is YAML too
    code = main(["scenarios", "match", rule, "not Fri and could we move it", "--start", "2025-03-03T09:00"])
    out = capsys.readouterr().out
    assert code == 1
    assert "FAIL: any of: none holds (" in out
    assert "found 'move' in clause \"not Fri and could we move it\" but it is negated by 'not'" in out
    assert "mentions_day day+3 (Thu 6 Mar)" in out


def test_match_reads_the_text_from_standard_input(
    capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr("sys.stdin", io.StringIO("Thursday is out.\nFriday works\n"))
    assert main(["scenarios", "match", "{affirms: thursday}", "-"]) == 1
    out = capsys.readouterr().out
    assert "1. \"Thursday is out\"  negated by 'is out'" in out and '2. "Friday works"' in out


@pytest.mark.parametrize(
    ("rule", "said"),
    [
        (
            "{contain_any: [thu]}",
            "RULE: contain_any: 'contain_any' is not an operator. Did you mean 'contains_any'",
        ),
        ("{affirms: []}", "RULE: (rule): 'affirms' needs a string or a list of non-empty strings"),
        ("{affirms: [", "RULE: (rule): not valid YAML"),
    ],
)
def test_match_reports_a_broken_rule_as_the_loader_does(
    rule: str, said: str, capsys: pytest.CaptureFixture[str]
) -> None:
    assert main(["scenarios", "match", rule, "Thursday works"]) == 2
    err = capsys.readouterr().err
    assert "RULE: 1 problem:" in err and said in err


def test_the_gate_says_why_a_passing_variant_failed(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], wide_console: None
) -> None:
    data = sound()
    data["goals"].append(
        {
            "id": "moved",
            "description": "The assistant asked to move it.",
            "checks": [
                {
                    "judge": {
                        "criterion": "asks to move the meeting",
                        "action": {"tool": ["email__reply_to_email", "email__send_email"]},
                        "fallback": {"affirms": "thursday"},
                    }
                }
            ],
        }
    )
    passing = next(variant for variant in data["variants"] if variant["expect"] == "pass")
    for action in passing["interventions"][0]["actions"]:
        if "content" in action["args"]:
            action["args"]["content"] = "Friday is out so Thursday works"
    _write(tmp_path, data)
    assert main(["scenarios", "check", str(tmp_path)]) == 1
    out = " ".join(capsys.readouterr().out.split())  # the console wraps long lines
    assert f"[variant:{passing['id']}]: check failed: moved[0] no judge model; fallback affirms" in out
    assert (
        "found 'Thursday' in clause \"Friday is out so Thursday works\" but it is negated by 'is out'" in out
    )


def test_check_lists_the_events_each_run_set_off_and_the_branch_each_reaction_took(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], wide_console: None
) -> None:
    _write(tmp_path, sound())
    assert main(["scenarios", "check", "-v", str(tmp_path)]) == 0
    lines = capsys.readouterr().out.splitlines()
    reply = '09:12 ann_confirms (reply: "Great, see you!", after #8 assistant email.reply_to_email)'
    assert f"  [oracle] events: 09:05 ann_asks; {reply}" in lines
    otherwise = '09:12 ann_confirms (otherwise: "Which day?", after #8 assistant email.reply_to_email)'
    assert f"  [variant:declines] events: 09:05 ann_asks; {otherwise}" in lines
    assert "  [nothing] events: 09:05 ann_asks" in lines
    # the busy user never waits: the clock still reaches Ann's email and her answer
    assert any(line.startswith("  [busy_user] events: 09:05 ann_asks; ") for line in lines)
    assert any(line.startswith("│ busy_user ") and "pass" in line for line in lines)


def _with_unread_lunch() -> dict[str, Any]:
    """The fair scenario whose oracle also books a lunch no check reads (so some of its mutants survive),
    with one of them declared equivalent."""
    data = sound()
    lunch = {
        "tool": "calendar__add_calendar_event",
        "args": {"title": "Lunch with Ann", "start_datetime": "day+3 12:30", "end_datetime": "day+3 13:30"},
    }
    data["oracle"]["interventions"][0]["actions"].append(lunch)
    data["equivalent_mutants"] = {"shift_time:1.2:+1d": "Ann did not say which day lunch is."}
    return data


def test_check_with_mutants_states_the_score_and_names_each_mutant(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], wide_console: None
) -> None:
    _write(tmp_path, _with_unread_lunch())
    assert main(["scenarios", "check", "--mutants", str(tmp_path)]) == 1  # survivors are breaches
    out = capsys.readouterr().out
    assert "mutants: 5 generated, 2 killed, 1 declared, 2 survived; rewrites: 2 of 2 pass" in out
    assert "surviving mutant tiny_reply drop_action:1.2 (left out calendar__add_calendar_event)" in out
    breaches = out[out.index("breach(es):") :]
    assert "tiny_reply: mutant drop_action:1.2 (left out calendar__add_calendar_event) passes" in breaches
    assert "shift_time:1.2:+1h" in breaches and "shift_time:1.2:+1d" not in breaches  # declared is fine
    # without --mutants none is played, but a lunch no check reads is a breach by itself
    assert main(["scenarios", "check", str(tmp_path)]) == 1
    out = capsys.readouterr().out
    assert "mutant" not in out[out.index("breach(es):") :]
    assert "unread field [oracle] #9 calendar__add_calendar_event writes 'title'" in out
    assert main(["scenarios", "check", "--mutants", "-v", str(tmp_path)]) == 1
    out = capsys.readouterr().out
    rows = {line.split("│")[1].strip(): line for line in out.splitlines() if line.count("│") > 4}
    assert "killed" in rows["drop_action:1.1"] and "survived" in rows["shift_time:1.2:+1h"]
    assert "killed" in rows["send_as_draft:1.1"]
    assert "declared" in rows["shift_time:1.2:+1d"] and "passed" in rows["reorder:1.1"]


def test_stats_with_mutants_shows_the_mutation_score(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], wide_console: None
) -> None:
    _write(tmp_path, _with_unread_lunch())
    assert main(["scenarios", "stats", "--mutants", "-j", "1", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert "mutants: 5 generated, 2 killed, 1 declared, 2 survived; rewrites: 2 of 2 pass" in out
    assert "mutation score: 60.0% of 5 mutants killed or declared equivalent (40.0% killed)" in out
    assert main(["scenarios", "stats", str(tmp_path)]) == 0
    assert "mutation score" not in capsys.readouterr().out  # playing them is asked for


def test_check_without_mutants_plays_none(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], wide_console: None
) -> None:
    _write(tmp_path, sound())
    assert main(["scenarios", "check", str(tmp_path)]) == 0
    assert "mutants:" not in capsys.readouterr().out
