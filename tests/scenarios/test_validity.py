"""Scenarios that judge the assistant fairly: variants proven by the gate, attribution, reactive branches,
slack and the by-hand run, on a small scenario built for the purpose."""

from __future__ import annotations

import copy
from typing import Any

import pytest

from pare.agents import SilentAssistant
from pare.bench import run_episode
from pare.bench.selftest import check_scenario
from pare.scenarios import OracleAssistant, OracleUser
from pare.scenarios.oracle import SlowUser
from tests.scenarios.helpers import REPLY, base, fair, intervention, parse, sound


def test_a_fair_scenario_passes_every_run_of_the_gate() -> None:
    verdict = check_scenario(parse(sound()))
    assert verdict.ok, verdict.breaches()
    runs = {run.run: run for run in verdict.runs}
    assert list(runs) == [
        "oracle",
        "slow_user",
        "busy_user",
        "nothing",
        "user_alone",
        "by_hand",
        "unrelated",
        "variant:fresh_email",
        "variant:declines",
        "variant:wrong_person",
    ]
    assert runs["variant:declines"].why == "Saying Thursday does not work is not a yes."
    assert runs["slow_user"].turns is not None and runs["oracle"].turns is not None
    assert runs["slow_user"].turns > runs["oracle"].turns
    assert not verdict.warnings


def test_a_variant_judged_otherwise_than_declared_is_a_breach() -> None:
    data = sound()
    data["variants"][1]["expect"] = "pass"
    del data["variants"][1]["fails"]
    data["variants"].append({**data["variants"][2], "id": "wrong_person_2"})
    verdict = check_scenario(parse(data))
    assert not verdict.ok
    first, judged = verdict.breaches()  # the state check, then the judge check's fallback on what Ann read
    assert first == (
        "tiny_reply [variant:declines]: check failed: replied[0] email.emails: 0 of 4 items match "
        "{folder: equals 'SENT', recipients: contains ['ann@x.example'], "
        "content: mentions_day 'day+3 00:00'}, 0 of them made by the assistant; wanted at least 1"
    )
    assert judged.startswith("tiny_reply [variant:declines]: check failed: replied[2] no judge model")


def test_a_near_miss_must_fail_the_goals_it_names() -> None:
    data = sound()
    data["goals"].append(
        {"id": "polite", "description": "d", "checks": [{"action": {"app": "email", "kind": "write"}}]}
    )
    data["variants"][2]["fails"] = ["polite"]
    breaches = check_scenario(parse(data)).breaches()
    assert breaches == [
        "tiny_reply [variant:wrong_person]: goal 'polite' should fail "
        "(Bob asked about Friday lunch, not Ann.) but was met"
    ]


def test_the_gate_demands_variants_and_by_hand_steps() -> None:
    data = sound()
    data["variants"] = data["variants"][1:2]
    data["oracle"]["by_hand"] = []
    verdict = check_scenario(parse(data))
    assert [line.split(": ", 1)[1][:40] for line in verdict.breaches()] == [
        "declares 0 passing variant(s); at least ",
        "declares 1 failing variant(s); at least ",
        "declares no oracle.by_hand steps: how th",
    ]


def test_the_by_hand_user_gets_turns_for_every_step_and_each_must_be_played() -> None:
    data = sound()
    # Longer than the default 10 turns: still played to the end, and still failing (the work is the user's).
    data["oracle"]["by_hand"] = [{"tool": "get_current_time"}] * 12 + data["oracle"]["by_hand"]
    runs = {run.run: run for run in check_scenario(parse(data)).runs}
    assert runs["by_hand"].ok and runs["by_hand"].turns is not None and runs["by_hand"].turns > 12

    never = {"action": {"actor": "user", "tool": "email__delete"}}  # nobody deletes anything
    data["oracle"]["by_hand"].append({"tool": "go_home", "when": never})
    breaches = check_scenario(parse(data)).breaches()
    assert any("by_hand played" in line and "never came" in line for line in breaches), breaches


def test_a_reactive_event_that_never_fires_is_a_breach() -> None:
    data = sound()
    data["events"][1]["when"]["args"]["email_id"] = "e1"
    breaches = check_scenario(parse(data)).breaches()
    assert "tiny_reply [oracle]: reactive event 'ann_confirms' never fired in the oracle run" in breaches[0]


def test_a_reply_that_restates_the_answer_is_warned_about() -> None:
    data = sound()
    event = data["events"][1]
    del event["if_args"], event["otherwise"], event["judge"]
    event["args"]["content"] = "Thursday then, great!"
    (warning,) = check_scenario(parse(data)).warnings
    assert "reactive event 'ann_confirms' fires on any matching action" in warning
    assert "goal 'replied'" in warning and "mentions_day" in warning


def test_the_world_reacts_to_what_was_written() -> None:
    scenario = parse(sound())
    right = run_episode(scenario, OracleUser(scenario), OracleAssistant(scenario))
    assert "ann_confirms" in right.env.scheduler.completed
    assert "ann_confirms_otherwise" not in right.env.scheduler.completed
    wrong = scenario.solution("declines")
    result = run_episode(scenario, OracleUser(scenario, wrong), OracleAssistant(scenario, wrong))
    assert "ann_confirms_otherwise" in result.env.scheduler.completed
    assert "ann_confirms" not in result.env.scheduler.completed
    assert result.env.snapshot()["email"]["emails"]["e_what"]["content"] == "Which day?"


def test_a_reply_corrected_before_the_question_back_was_due_gets_no_question() -> None:
    data = sound()
    data["oracle"]["interventions"] = [
        intervention(
            {**REPLY, "args": {"email_id": "e_ann", "content": "Friday?"}},
            {**REPLY, "args": {"email_id": "e_ann", "content": "Sorry, I meant Friday... no."}},
            REPLY,
        )
    ]
    scenario = parse(data)
    result = run_episode(scenario, OracleUser(scenario), OracleAssistant(scenario))
    fired = [entry.event_id for entry in result.env.log if entry.actor == "env" and entry.ok]
    assert fired == ["ann_asks", "ann_confirms"]  # the right answer came within the otherwise's 5 minutes
    assert result.env.scheduler.withdrawn == {"ann_confirms_otherwise": "ann_confirms"}
    assert check_scenario(scenario).ok  # the gate lists no otherwise branch for it


def test_a_reply_corrected_after_the_question_back_gets_both_and_the_question_once() -> None:
    data = sound()
    wrong = {**REPLY, "args": {"email_id": "e_ann", "content": "Friday?"}}
    later = {
        **intervention(REPLY),
        "when": {"event": "ann_confirms_otherwise"},
        "proposal": "Tell Ann: Thursday.",
    }
    data["oracle"]["interventions"] = [intervention(wrong, wrong), later]
    scenario = parse(data)
    result = run_episode(scenario, OracleUser(scenario), OracleAssistant(scenario))
    fired = [entry.event_id for entry in result.env.log if entry.actor == "env" and entry.ok]
    assert fired == ["ann_asks", "ann_confirms_otherwise", "ann_confirms"]
    assert not result.env.scheduler.withdrawn


def test_the_users_own_work_is_not_the_assistants() -> None:
    scenario = parse(fair())  # its one state check is the one the user's own reply cannot meet
    result = run_episode(scenario, OracleUser(scenario, scenario.by_hand()), SilentAssistant())
    assert not result.success and result.outcome.user_did_work
    (failure,) = result.outcome.failures()
    assert failure.user_made and "0 of them made by the assistant" in failure.detail
    reply = next(e for e in result.env.snapshot()["email"]["emails"].values() if e["folder"] == "SENT")
    mark = result.env.attribution.mark(("email", "emails", reply["email_id"]))
    assert mark is not None and mark.created_by == "user" and mark.changed_by == "user"
    assert result.trajectory().marks[f"email.emails.{reply['email_id']}"].created_by == "user"
    oracle = run_episode(scenario, OracleUser(scenario), OracleAssistant(scenario))
    assert oracle.success and not oracle.outcome.user_did_work


def test_silence_is_not_the_user_doing_the_work() -> None:
    scenario = parse(sound())
    result = run_episode(scenario, OracleUser(scenario), SilentAssistant())
    assert not result.success and not result.outcome.user_did_work


def test_world_events_are_not_attributed_to_anyone() -> None:
    scenario = parse(sound())
    result = run_episode(scenario, OracleUser(scenario), OracleAssistant(scenario))
    assert result.env.attribution.mark(("email", "emails", "e_ann")) is None  # arrived from the world
    assert result.env.attribution.mark(("email", "emails", "e_conf")) is None


def test_the_slow_user_looks_at_the_clock_before_each_step_and_answer() -> None:
    scenario = parse(sound())
    result = run_episode(scenario, SlowUser(scenario), OracleAssistant(scenario))
    tools = [step.action.tool for step in result.steps if step.actor == "user" and step.action.tool != "wait"]
    assert tools == [
        "get_current_time",
        "open_app",
        "get_current_time",
        "open_email",
        "get_current_time",
        "accept_proposal",
    ]
    assert result.success


def test_a_scenario_without_slack_fails_the_slow_user_run() -> None:
    data = sound()
    steps = [{"tool": "go_back"}, {"tool": "open_email", "args": {"email_id": "e_ann"}}] * 3
    data["oracle"]["user"] = [*data["oracle"]["user"], *steps]
    data["oracle"]["interventions"][0]["when"] = {
        "action": {"actor": "user", "tool": "email__open_email"},
        "event": "ann_asks",
    }
    data["oracle"]["interventions"][0]["when"]["action"]["args"] = {"email_id": "e_ann"}
    data["goals"][0]["checks"].append({"action": {"actor": "user", "tool": "system__go_back", "count": 3}})
    verdict = check_scenario(parse(data))
    assert verdict.run("oracle").ok
    slow = verdict.run("slow_user")
    assert not slow.ok and slow.turns == 10


@pytest.mark.parametrize(
    ("content", "passes"),
    [
        ("Yes, Thursday works for me!", True),
        ("Thu 6 March is perfect", True),
        ("See you on the 6th", True),
        ("Thursday does not work, sorry", False),
        ("Wednesday works, Thursday is out", False),
        ("I reviewed it, thanks", False),
    ],
)
def test_replies_are_read_for_meaning(content: str, passes: bool) -> None:
    data = sound()
    data["variants"].append(
        {
            "id": "worded",
            "expect": "pass" if passes else "fail",
            "why": "wording",
            "interventions": [intervention({**REPLY, "args": {"email_id": "e_ann", "content": content}})],
        }
    )
    verdict = check_scenario(parse(data))
    assert verdict.run("variant:worded").ok, verdict.breaches()


def no_proposal() -> dict[str, Any]:
    """Ann's question is for the user to answer: the right move is to watch and wait."""
    data = sound()
    data["id"] = "ann_asks_sam_himself"
    data["kind"] = "no_proposal"
    data["events"] = data["events"][:1]
    data["oracle"] = {"user": data["oracle"]["user"], "interventions": []}
    data["goals"] = [
        {
            "id": "left_alone",
            "description": "The assistant did not push a reply the user wants to write.",
            "checks": [{"no_action": {"tool": "agent_ui__send_message_to_user", "mode": "observe"}}],
        }
    ]
    eager = intervention(REPLY)
    data["variants"] = [
        {
            "id": "user_reads_more",
            "expect": "pass",
            "why": "The user also reading Bob's email changes nothing.",
            "user": [
                *data["oracle"]["user"],
                {"tool": "go_back"},
                {"tool": "open_email", "args": {"email_id": "e1"}},
            ],
        },
        {"id": "eager_reply", "expect": "fail", "why": "Replying for the user.", "interventions": [eager]},
        {
            "id": "eager_event",
            "expect": "fail",
            "why": "Booking Thursday before the user decided.",
            "interventions": [
                {
                    **eager,
                    "actions": [
                        {
                            "tool": "calendar__add_calendar_event",
                            "args": {
                                "title": "Ann",
                                "start_datetime": "day+3 12:00",
                                "end_datetime": "day+3 13:00",
                            },
                        }
                    ],
                }
            ],
        },
    ]
    return data


def test_a_no_proposal_scenario_turns_the_gate_round() -> None:
    verdict = check_scenario(parse(no_proposal()))
    assert verdict.ok, verdict.breaches()
    assert [run.run for run in verdict.runs] == [
        "oracle",
        "slow_user",
        "busy_user",
        "unrelated",
        "variant:user_reads_more",
        "variant:eager_reply",
        "variant:eager_event",
    ]
    assert [run.expected_success for run in verdict.runs] == [True, True, True, False, True, False, False]


def test_a_near_miss_may_be_declared_to_fail_through_a_side_effect_or_an_invented_detail() -> None:
    data = base()
    wrong = copy.deepcopy(data["oracle"]["interventions"])
    wrong[0]["actions"][0]["args"]["content"] = "Thursday works, see you at 15:20!"
    data["variants"] = [
        {"id": "invents", "expect": "fail", "why": "15:20 is made up", "fails": ["invented_details"],
         "interventions": wrong},
        {"id": "claims_a_change", "expect": "fail", "why": "w", "fails": ["side_effects"],
         "interventions": wrong},
    ]  # fmt: skip
    verdict = check_scenario(parse(data), runs={"oracle", "variant:invents", "variant:claims_a_change"})
    assert verdict.run("variant:invents").ok
    (problem,) = verdict.run("variant:claims_a_change").problems
    assert "should make a side effect" in problem


def test_a_scripted_step_that_never_came_is_a_problem_of_the_run() -> None:
    data = base()
    steps = copy.deepcopy(data["oracle"]["user"])
    # nothing is left to come after the reply: the wait ends the episode, and the last step never plays
    steps += [{"tool": "wait"}, {"tool": "go_home"}, {"tool": "open_app", "args": {"app_name": "calendar"}}]
    data["variants"] = [{"id": "waits_then_looks", "expect": "pass", "why": "w", "user": steps}]
    verdict = check_scenario(parse(data), runs={"oracle", "variant:waits_then_looks"})
    problems = verdict.run("variant:waits_then_looks").problems
    assert any("played 3 of its 5 user steps" in problem for problem in problems), problems
