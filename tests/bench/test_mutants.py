"""The gate's generated mutants (which the checks must fail) and rewrites (which they must pass)."""

from __future__ import annotations

import functools
from typing import Any

import pytest

from pare.bench.selftest import MutantVerdict, ScenarioVerdict, check_scenario
from pare.scenarios.library import load_scenarios
from pare.scenarios.loader import ScenarioError
from pare.scenarios.model import Scenario
from pare.scenarios.mutants import _other_date_forms, mutants, rewrites
from tests.scenarios.helpers import base, parse


@functools.cache
def _library() -> dict[str, Scenario]:
    return {scenario.id: scenario for scenario in load_scenarios(None)}


def _played(scenario: Scenario) -> dict[str, MutantVerdict]:
    verdict = check_scenario(scenario, runs=("oracle",), variants=False, mutants=True)
    return {mutant.name: mutant for mutant in verdict.mutants}


def test_mutants_are_named_by_operator_and_the_same_every_time() -> None:
    scenario = _library()["dress_rehearsal_clashes_with_school_pickup"]
    first = [(m.name, m.what, m.solution) for m in mutants(scenario)]
    assert first == [(m.name, m.what, m.solution) for m in mutants(scenario)]
    assert [name for name, _, _ in first] == [
        "swap_person:1.1:user_id",
        "shift_time:1.2:+1d",
        "shift_time:1.2:+1h",
        "shift_text_time:1.1:content",
        "drop_action:1.1",
        "drop_action:1.2",
    ]
    # the other person is one of the seed's, and the user is never chosen
    person = dict((name, what) for name, what, _ in first)["swap_person:1.1:user_id"]
    swapped_to = person.rpartition(" -> ")[2]
    assert swapped_to in scenario.seed["messaging"]["users"] and swapped_to != "user-jonas"
    assert swapped_to != scenario.seed["messaging"]["current_user_id"]


def test_a_shifted_time_moves_the_start_and_the_end_together() -> None:
    scenario = _library()["dress_rehearsal_clashes_with_school_pickup"]
    by_name = {m.name: m for m in mutants(scenario)}
    [action] = [
        a for a in by_name["shift_time:1.2:+1d"].solution.interventions[0].actions if "title" in a.args
    ]
    assert (action.args["start_datetime"], action.args["end_datetime"]) == ("day+3 17:00", "day+3 19:00")
    [action] = [
        a for a in by_name["shift_time:1.2:+1h"].solution.interventions[0].actions if "title" in a.args
    ]
    assert (action.args["start_datetime"], action.args["end_datetime"]) == ("day+2 18:00", "day+2 20:00")


def test_wrong_person_day_hour_and_left_out_action_are_killed_and_rewrites_pass() -> None:
    played = _played(_library()["dress_rehearsal_clashes_with_school_pickup"])
    assert {name: m.outcome for name, m in played.items()} == {
        "swap_person:1.1:user_id": "killed",
        "shift_time:1.2:+1d": "killed",
        "shift_time:1.2:+1h": "killed",
        "shift_text_time:1.1:content": "killed",
        "drop_action:1.1": "killed",
        "drop_action:1.2": "killed",
        "reorder:1.1": "passed",
        "time_phrasing:1.1:content": "passed",
        "time_phrasing:1.1:content:words": "passed",
        "time_phrasing:1.1:content:spoken": "passed",
        "split_message:1.1": "passed",
    }
    assert played["drop_action:1.2"].detail.startswith("check failed: ")


def test_rewrites_say_the_same_thing_another_way() -> None:
    scenario = _library()["dress_rehearsal_clashes_with_school_pickup"]
    by_name = {m.name: m for m in rewrites(scenario)}
    oracle = scenario.oracle.interventions[0].actions
    reordered = by_name["reorder:1.1"].solution.interventions[0].actions
    assert [a.tool for a in reordered] == [a.tool for a in reversed(oracle)]
    phrased = by_name["time_phrasing:1.1:content"].solution.interventions[0].actions[0].args["content"]
    assert "Wednesday 5pm-7pm" in phrased and "at 5:15pm" in phrased and "17:" not in phrased
    said = by_name["time_phrasing:1.1:content:words"].solution.interventions[0].actions[0].args["content"]
    assert "5pm-7pm" in said and "at 5.15 in the afternoon" in said  # a range keeps the short form
    later = _by_name(scenario.id, "shift_text_time")["shift_text_time:1.1:content"]
    told = later.solution.interventions[0].actions[0].args["content"]
    assert "6pm-8pm" in told and "at quarter past six in the evening" in told  # 17:15 an hour later
    spoken = by_name["time_phrasing:1.1:content:spoken"].solution.interventions[0].actions[0].args["content"]
    assert "5pm-7pm" in spoken and "at quarter past five in the afternoon" in spoken
    halves = by_name["split_message:1.1"].solution.interventions[0].actions[:2]
    assert [a.tool for a in halves] == ["messaging__send_message"] * 2
    assert " ".join(a.args["content"] for a in halves) == oracle[0].args["content"]


def test_another_product_a_changed_quantity_and_an_extra_write_to_a_distractor_are_killed() -> None:
    scenario = _library()["air_purifier_filter_substitute_within_spec"]
    played = _played(scenario)
    for name in ("extra_write:1.4:item_id", "swap_item:1.4:item_id", "change_number:1.4:quantity"):
        assert played[name].outcome == "killed", (name, played[name])
    # the extra write keeps the asked one and adds another on an item no right solution touches
    extra = next(m for m in mutants(scenario) if m.name == "extra_write:1.4:item_id")
    carted = [
        a.args["item_id"] for a in extra.solution.interventions[0].actions if a.tool.endswith("add_to_cart")
    ]
    assert carted[0] == "ff-26-h13" and carted[1] != "ff-26-h13"


def test_a_second_unasked_write_no_check_names_is_killed_by_side_effects() -> None:
    played = _played(_library()["dry_cleaner_ready_thursday_pickup_reminder"])
    extra = played["extra_write:1.1:reminder_id"]
    assert extra.outcome == "killed"
    assert extra.detail.startswith("side effect: changed reminder.reminders ")


def test_another_file_of_the_seed_attached_is_killed() -> None:
    scenario = _library()["accountant_asks_for_last_three_payslips"]
    played = _played(scenario)
    swapped = {name: m for name, m in played.items() if name.startswith("swap_file:")}
    assert sorted(swapped) == [f"swap_file:1.1:attachments[{i}]" for i in range(3)]
    assert all(m.outcome == "killed" for m in swapped.values()), swapped
    assert played["split_message:1.1"].outcome == "passed"


def test_an_email_kept_as_a_draft_is_killed() -> None:
    scenario = _library()["bounced_email_typo_resend_to_contact"]
    [draft] = [m for m in mutants(scenario) if m.operator == "send_as_draft"]
    [saved] = [a for a in draft.solution.interventions[0].actions if a.tool == "email__save_draft"]
    sent = next(a for a in scenario.oracle.interventions[0].actions if a.tool == "email__send_email")
    assert saved.args == sent.args
    assert _played(scenario)[draft.name].outcome == "killed"


def _by_name(scenario_id: str, operator: str) -> dict[str, Any]:
    scenario = _library()[scenario_id]
    return {m.name: m for m in [*mutants(scenario), *rewrites(scenario)] if m.operator == operator}


def test_the_other_offered_slot_is_taken_and_killed() -> None:
    # the practice offers two new times; the mutant books the one the oracle did not
    [(name, slot)] = _by_name("dentist_moves_checkup", "other_slot").items()
    assert name == "other_slot:1.1" and "Wed 05 Mar 17:15" in slot.what
    assert _played(_library()["dentist_moves_checkup"])[name].outcome == "killed"


def test_the_most_alike_distractor_is_chosen_and_killed() -> None:
    scenario = _library()["air_purifier_filter_substitute_within_spec"]
    [(name, similar)] = _by_name(scenario.id, "similar_item").items()
    assert similar.what.endswith("ff-26-h13 -> ff-30-h13, the most alike in the seed")
    assert _played(scenario)[name].outcome == "killed"


def test_a_proposal_before_the_fact_that_justifies_it_is_killed() -> None:
    scenario = _library()["train_delay_push_station_pickup_later"]
    early = _by_name(scenario.id, "early_proposal")["early_proposal:1"]
    assert early.solution.interventions[0].when is None
    played = _played(scenario)["early_proposal:1"]
    # killed by the check that the pickup is rebooked only once the 45-minute delay is known
    assert played.outcome == "killed" and played.detail.startswith("check failed: pickup_matches_arrival[0]")


def test_a_proposal_whose_event_comes_first_anyway_is_stillborn() -> None:
    # Priya answers a minute after the question: proposing "at once" after it already follows her answer
    played = _played(_library()["flatmate_away_restock_order"])["early_proposal:2"]
    assert played.outcome == "stillborn" and "priya_reply" in played.detail


def test_a_reply_as_a_new_email_a_renamed_file_and_dates_written_another_way_pass() -> None:
    scenario = _library()["accountant_asks_for_last_three_payslips"]
    played = _played(scenario)
    new = _by_name(scenario.id, "reply_as_new")["reply_as_new:1.1"]
    [sent] = [a for a in new.solution.interventions[0].actions if a.tool == "email__send_email"]
    assert sent.args["recipients"] == ["rhona@fergusonblake.example"] and sent.args["subject"].startswith(
        "Re: "
    )
    renamed = _by_name(scenario.id, "rename_file")["rename_file:1.1"]
    copies = [
        a.args["destination"]
        for a in renamed.solution.interventions[0].actions
        if a.tool == "files__copy_file"
    ]
    assert len(copies) == 3 and all("/attachment-" in path for path in copies)
    for name in ("reply_as_new:1.1", "rename_file:1.1", "date_phrasing:1.1:content"):
        assert played[name].outcome == "passed", (name, played[name])


def test_an_update_done_as_delete_and_add_passes_and_an_event_with_attendees_is_left_alone() -> None:
    scenario = _library()["dry_cleaner_ready_thursday_pickup_reminder"]
    readd = _by_name(scenario.id, "delete_readd")["delete_readd:1.1"]
    assert [a.tool for a in readd.solution.interventions[0].actions][-2:] == [
        "reminder__delete_reminder",
        "reminder__add_reminder",
    ]
    assert _played(scenario)["delete_readd:1.1"].outcome == "passed"
    # re-adding a meeting would invite its attendees again: not the same solution
    assert not _by_name("dentist_moves_checkup", "delete_readd")


def test_a_new_email_sent_as_a_reply_on_the_same_subject_passes() -> None:
    scenario = _library()["bounced_email_typo_resend_to_contact"]
    [(name, reply)] = _by_name(scenario.id, "new_as_reply").items()
    assert reply.solution.interventions[0].actions[1].args["email_id"] == "email-401"
    assert _played(scenario)[name].outcome == "passed"


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        ("Due 2026-06-04, see you then.", "Due 4 June 2026, see you then."),
        ("On 4 June at the hall", "On June 4th at the hall"),
        ("By June 21 please", "By 21 June please"),
        ("No date here", "No date here"),
    ],
)
def test_dates_are_written_in_another_common_form(text: str, expected: str) -> None:
    assert _other_date_forms(text) == expected


# -- a scenario whose checks leave the day open ----------------------------------------------------
def _lunch(**extra: Any) -> Scenario:
    """Tiny scenario: the assistant puts lunch with Ann in the calendar; the checks read only the title."""
    data = base()
    data["oracle"]["interventions"][0]["actions"] = [
        {
            "tool": "calendar__add_calendar_event",
            "args": {
                "title": "Lunch with Ann",
                "start_datetime": "day+3 12:30",
                "end_datetime": "day+3 13:30",
            },
        }
    ]
    data["goals"] = [
        {
            "id": "lunch",
            "description": "Lunch is in the calendar.",
            "checks": [
                {
                    "state": {
                        "path": "calendar.events",
                        "by": "assistant",
                        "where": {"title": "Lunch with Ann"},
                    }
                }
            ],
        }
    ]
    data.update(extra)
    return parse(data)


def test_a_mutant_the_checks_miss_survives_unless_declared_with_a_reason() -> None:
    reason = "Ann said any day this week works."
    verdict = check_scenario(
        _lunch(equivalent_mutants={"shift_time:1.1:+1d": reason}),
        runs=("oracle",),
        variants=False,
        mutants=True,
    )
    outcomes = {m.name: (m.outcome, m.detail) for m in verdict.mutants}
    assert outcomes["shift_time:1.1:+1d"] == ("declared", reason)
    assert outcomes["shift_time:1.1:+1h"] == ("survived", "")
    assert outcomes["drop_action:1.1"][0] == "killed"
    assert all(run.ok for run in verdict.runs)  # the runs themselves are fine ...
    assert not verdict.ok  # ... but a survivor is a breach of the gate, named with what it changed
    assert [line for line in verdict.breaches() if "shift_time:1.1:+1h" in line]
    assert not [line for line in verdict.breaches() if "shift_time:1.1:+1d" in line]


def test_a_declaration_the_checks_contradict_or_the_generator_never_makes_is_warned() -> None:
    verdict = check_scenario(
        _lunch(equivalent_mutants={"drop_action:1.1": "not needed", "swap_person:1.1:attendees": "old"}),
        runs=("oracle",),
        variants=False,
        mutants=True,
    )
    assert any("'drop_action:1.1', which the checks kill" in line for line in verdict.warnings)
    assert any("'swap_person:1.1:attendees', which is not generated" in line for line in verdict.warnings)


@pytest.mark.parametrize(
    ("declared", "problem"),
    [
        ({"shift_time:1.1:+1d": ""}, "at least 1 character"),
        ({"shift_time": "a reason"}, "write <operator>:<where>"),
        ({"shift_tim:1.1:+1d": "a reason"}, "unknown mutant operator 'shift_tim'"),
        ({"reorder:1.1": "a reason"}, "a rewrite must pass"),
    ],
)
def test_a_bad_declaration_is_refused_with_the_reason(declared: dict[str, str], problem: str) -> None:
    with pytest.raises(ScenarioError) as error:
        _lunch(equivalent_mutants=declared)
    assert problem in str(error.value)


def test_survivors_and_failing_rewrites_are_breaches_and_stillborn_mutants_are_not() -> None:
    played = (
        MutantVerdict("drop_action:1.1", "fail", "left out x", "killed", "check failed: a"),
        MutantVerdict("shift_time:1.1:+1d", "fail", "due +1d", "survived"),
        MutantVerdict("extra_write:1.1:item_id", "fail", "also on y", "stillborn"),
        MutantVerdict("swap_person:1.1:to", "fail", "to: a -> b", "declared", "either may be told"),
        MutantVerdict("split_message:1.1", "pass", "sent in two messages", "failed", "check failed: told"),
        MutantVerdict("reorder:1.1", "pass", "1.1 after 1.2", "passed"),
    )
    verdict = ScenarioVerdict("s", runs=(), seconds=0.0, mutants=played)
    assert not verdict.ok
    assert verdict.breaches() == [
        "s: mutant shift_time:1.1:+1d (due +1d) passes the checks: tighten them, or declare it in "
        "equivalent_mutants with the reason it is right",
        "s: rewrite split_message:1.1 (sent in two messages) fails the checks: check failed: told",
    ]
    judged = tuple(m for m in played if m.outcome not in ("survived", "failed"))
    assert ScenarioVerdict("s", runs=(), seconds=0.0, mutants=judged).ok
