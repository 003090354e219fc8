"""A person told is told, whatever the channel; a file is its content.

Unit tests on a small scenario (every channel, for checks and for the world's reactions alike), then
probes on library scenarios: correct solutions their authors did not write down must pass, and a message
to someone else, or a different file under the right name, must still fail.
"""

from __future__ import annotations

from typing import Any

import pytest

from pare.bench.selftest import check_scenario
from pare.env import Environment
from pare.errors import UserInputError
from pare.scenarios import Scenario
from pare.scenarios.build import build_environment
from pare.scenarios.checks import evaluate
from pare.scenarios.library import get_scenario
from pare.scenarios.model import Variant
from pare.scenarios.told import conversation_members, email_addressees
from tests.scenarios.helpers import base, parse

ANN = "ann@x.example"


def _scenario(*checks: dict[str, Any], events: list[dict[str, Any]] | None = None) -> Scenario:
    """The tiny scenario with messaging (Ann and Bob, a group with both) and the given checks."""
    data = base()
    data["apps"] = ["email", "calendar", "messaging", "files"]
    data["seed"]["messaging"] = {
        "users": {"user-me": "Me", "user-ann": "Ann", "user-bob": "Bob"},
        "conversations": [
            {"conversation_id": "conv-ann", "participant_ids": ["user-me", "user-ann"]},
            {
                "conversation_id": "conv-team",
                "participant_ids": ["user-me", "user-ann", "user-bob"],
                "title": "Team",
            },
            {"conversation_id": "conv-bob", "participant_ids": ["user-me", "user-bob"]},
        ],
    }
    data["seed"]["files"] = {
        "files": {
            "/Documents/menu.txt": {"content": "Thursday lunch menu: soup, bread."},
            "/Documents/stew.txt": {"content": "Last week's menu: stew."},
        }
    }
    data["goals"] = [{"id": "told", "description": "Ann knows.", "checks": list(checks)}]
    data["events"].extend(events or [])
    return parse(data)


def _played(scenario: Scenario, *calls: tuple[str, dict[str, Any]]) -> tuple[Environment, bool]:
    """The scenario's world after the assistant's ``calls``, and whether its goal was met."""
    env = build_environment(scenario)
    env.advance_to(scenario.start.replace(minute=10))  # Ann's email has arrived
    for tool, args in calls:
        result = env.call("assistant", tool, args, mode="execute")
        assert result.ok, result.error
    env.deliver_due_events()
    outcome = evaluate(scenario, env.log.entries, env.snapshot(shared=True), attribution=env.attribution)
    return env, outcome.success


TOLD_ANN = {"action": {"to": [ANN, "user-ann"], "args": {"content": {"contains": "thursday"}}}}


@pytest.mark.parametrize(
    "call",
    [
        ("email__send_email", {"recipients": [ANN], "subject": "Lunch", "content": "Thursday works."}),
        (
            "email__send_email",
            {"recipients": ["bob@x.example"], "cc": [ANN], "subject": "Lunch", "content": "Thursday works."},
        ),
        ("email__reply_to_email", {"email_id": "e_ann", "content": "Thursday works."}),
        ("messaging__send_message", {"user_id": "user-ann", "content": "Thursday works."}),
        (
            "messaging__send_message_to_group_conversation",
            {"conversation_id": "conv-team", "content": "Thursday!"},
        ),
    ],
    ids=["email", "cc", "reply", "chat", "group"],
)
def test_every_channel_that_reaches_the_person_tells_them(call: tuple[str, dict[str, Any]]) -> None:
    assert _played(_scenario(TOLD_ANN), call)[1]


@pytest.mark.parametrize(
    "call",
    [
        (
            "email__send_email",
            {"recipients": ["bob@x.example"], "subject": "Lunch", "content": "Thursday works."},
        ),
        ("messaging__send_message", {"user_id": "user-bob", "content": "Thursday works."}),
        (
            "messaging__send_message_to_group_conversation",
            {"conversation_id": "conv-bob", "content": "Thursday"},
        ),
        ("email__reply_to_email", {"email_id": "e1", "content": "Thursday works."}),  # Bob's email
        ("messaging__send_message", {"user_id": "user-ann", "content": "Friday works."}),
    ],
    ids=["email-to-bob", "chat-to-bob", "conversation-with-bob", "reply-to-bob", "wrong-words"],
)
def test_a_message_to_someone_else_or_without_the_words_tells_nothing(
    call: tuple[str, dict[str, Any]],
) -> None:
    assert not _played(_scenario(TOLD_ANN), call)[1]


def test_a_forward_tells_what_the_forwarded_email_says() -> None:
    forward = ("email__forward_email", {"email_id": "e_ann", "recipients": ["bob@x.example"]})
    told_bob = {
        "judge": {
            "criterion": "Bob learns that Ann asks about Thursday.",
            "action": {"to": "bob@x.example"},
            "fallback": {"contains": "thursday"},
        }
    }
    assert _played(_scenario(told_bob), forward)[1]
    assert not _played(
        _scenario(told_bob), ("email__forward_email", {"email_id": "e1", "recipients": ["bob@x.example"]})
    )[1]


def test_via_narrows_the_channel() -> None:
    by_email = {"action": {"to": [ANN, "user-ann"], "via": ["email"]}}
    in_the_thread = {"action": {"to": ANN, "via": ["reply"]}}
    chat = ("messaging__send_message", {"user_id": "user-ann", "content": "Thursday works."})
    fresh = ("email__send_email", {"recipients": [ANN], "subject": "Lunch", "content": "Thursday works."})
    reply = ("email__reply_to_email", {"email_id": "e_ann", "content": "Thursday works."})
    assert not _played(_scenario(by_email), chat)[1]
    assert _played(_scenario(by_email), fresh)[1]
    assert not _played(_scenario(in_the_thread), fresh)[1]
    assert _played(_scenario(in_the_thread), reply)[1]


def test_the_world_reacts_to_whoever_was_told_through_any_channel() -> None:
    reaction = {
        "id": "ann_answers",
        "when": {"to": [ANN, "user-ann"]},
        "if_args": {"content": {"mentions_day": "day+3"}},
        "tool": "messaging__receive_message",
        "args": {"message_id": "msg-ann-yes", "sender": "user-ann", "content": "Great!"},
        "otherwise": {
            "tool": "messaging__receive_message",
            "args": {"message_id": "msg-ann-which", "sender": "user-ann", "content": "Which day?"},
        },
    }
    scenario = _scenario(TOLD_ANN, events=[reaction])
    group = (
        "messaging__send_message_to_group_conversation",
        {"conversation_id": "conv-team", "content": "Thursday!"},
    )
    env, _ = _played(scenario, group)
    assert "ann_answers" in env.scheduler.completed
    env, _ = _played(
        scenario, ("email__send_email", {"recipients": [ANN], "cc": [], "subject": "x", "content": "Soon."})
    )
    assert "ann_answers_otherwise" in env.scheduler.completed
    env, _ = _played(scenario, ("messaging__send_message", {"user_id": "user-bob", "content": "Thursday!"}))
    assert not {"ann_answers", "ann_answers_otherwise"} & set(env.scheduler.completed)


def test_the_world_reads_what_the_person_was_told_together() -> None:
    reaction = {
        "id": "ann_answers",
        "when": {"to": [ANN, "user-ann"]},
        "if_args": {"content": {"mentions_time": "day+3 12:30"}},
        "tool": "messaging__receive_message",
        "args": {"message_id": "msg-ann-yes", "sender": "user-ann", "content": "Great!"},
    }
    scenario = _scenario(TOLD_ANN, events=[reaction])
    day = ("messaging__send_message", {"user_id": "user-ann", "content": "Lunch on Thursday?"})
    clock = ("email__send_email", {"recipients": [ANN], "subject": "Lunch", "content": "At 12:30, I mean."})
    env, _ = _played(scenario, day, clock)
    assert "ann_answers" in env.scheduler.completed  # the day in a message, the time in an email
    to_bob = ("messaging__send_message", {"user_id": "user-bob", "content": "At 12:30, I mean."})
    env, _ = _played(scenario, day, to_bob)
    assert "ann_answers" not in env.scheduler.completed  # what Bob was told, Ann was not


def _judged_told_ann(**options: Any) -> Scenario:
    judge = {
        "criterion": "Ann is told lunch is on Thursday at 12:30, and no other day.",
        "action": {"to": [ANN, "user-ann"]},
        "fallback": {"mentions_time": "day+3 12:30", "not": {"mentions_day": "day+4"}},
        **options,
    }
    return _scenario({"judge": judge})


DAY_TO_ANN = ("messaging__send_message", {"user_id": "user-ann", "content": "Lunch on Thursday?"})
CLOCK_TO_ANN = (
    "email__send_email",
    {"recipients": [ANN], "subject": "Lunch", "content": "At 12:30, I mean."},
)


def test_a_judge_of_what_a_person_was_told_reads_all_of_it_together() -> None:
    assert _played(_judged_told_ann(), DAY_TO_ANN, CLOCK_TO_ANN)[1]  # the facts over two messages
    assert not _played(_judged_told_ann(together=False), DAY_TO_ANN, CLOCK_TO_ANN)[1]
    right = ("messaging__send_message", {"user_id": "user-ann", "content": "Lunch Thursday at 12:30."})
    wrong = ("messaging__send_message", {"user_id": "user-ann", "content": "Or Friday, whichever."})
    assert _played(_judged_told_ann(), right)[1]
    assert not _played(_judged_told_ann(), right, wrong)[1]  # a contradicting message counts against


def test_a_renamed_copy_is_the_file_and_a_namesake_is_not() -> None:
    sent_menu = {"action": {"to": ANN, "args": {"attachments": {"contains": "menu.txt"}}}}
    scenario = _scenario(sent_menu)
    copy = ("files__copy_file", {"source": "/Documents/menu.txt", "destination": "/Downloads/for_ann.txt"})
    namesake = ("files__write_file", {"path": "/Downloads/menu.txt", "content": "Something else."})

    def reply(path: str) -> tuple[str, dict[str, Any]]:
        return "email__reply_to_email", {
            "email_id": "e_ann",
            "content": "Menu attached.",
            "attachments": [path],
        }

    assert _played(scenario, copy, reply("/Downloads/for_ann.txt"))[1]
    assert _played(scenario, reply("/Documents/menu.txt"))[1]
    assert not _played(scenario, namesake, reply("/Downloads/menu.txt"))[1]
    assert not _played(scenario, reply("/Documents/stew.txt"))[1]


def test_a_state_check_on_attachments_reads_them_by_content() -> None:
    in_sent = {
        "state": {
            "path": "email.emails",
            "by": "assistant",
            "where": {"folder": "SENT", "attachments": {"contains": "menu.txt"}},
        }
    }
    scenario = _scenario(in_sent)
    copy = ("files__copy_file", {"source": "/Documents/menu.txt", "destination": "/Downloads/x.txt"})
    reply = (
        "email__reply_to_email",
        {"email_id": "e_ann", "content": "Menu.", "attachments": ["/Downloads/x.txt"]},
    )
    assert _played(scenario, copy, reply)[1]
    other = ("files__write_file", {"path": "/Downloads/x.txt", "content": "Not the menu."})
    assert not _played(scenario, other, reply)[1]


@pytest.mark.parametrize(
    ("pattern", "message"),
    [
        ({"to": "nobody-here"}, "neither an email address nor a messaging user id"),
        ({"to": "ann@", "tool": "email__send_email"}, "is not an email address"),
        ({"to": ANN, "tool": "email__move_email"}, "tells no one anything"),
        ({"via": ["email"], "tool": "email__send_email"}, "'via' narrows 'to'"),
        ({"to": ANN, "via": ["fax"]}, "via"),
    ],
)
def test_bad_to_and_via_are_refused_with_the_reason(pattern: dict[str, Any], message: str) -> None:
    with pytest.raises(UserInputError, match=message):
        _scenario({"action": pattern})


# -- probes on library scenarios --------------------------------------------------------------------
def _probe(scenario_id: str, *variants: dict[str, Any]) -> dict[str, Any]:
    """Play ``variants`` (written as in a scenario file) on a library scenario: each run's verdict."""
    scenario = get_scenario(scenario_id)
    written = [{key: value for key, value in v.items() if value or key != "fails"} for v in variants]
    probes = scenario.model_copy(update={"variants": [Variant.model_validate(v) for v in written]})
    verdict = check_scenario(probes, runs=())
    return {run.run.removeprefix("variant:"): run for run in verdict.runs}


def _with_actions(scenario_id: str, index: int, actions: list[dict[str, Any]]) -> list[dict[str, Any]]:
    """The library oracle's interventions with the ``index``-th one doing ``actions``."""
    interventions = [i.model_dump(exclude_unset=True) for i in get_scenario(scenario_id).oracle.interventions]
    interventions[index]["actions"] = actions
    return interventions


def _variant(name: str, expect: str, interventions: list[dict[str, Any]], *fails: str) -> dict[str, Any]:
    return {"id": name, "expect": expect, "why": name, "fails": list(fails), "interventions": interventions}


def test_probe_a_cc_tells_the_practice() -> None:
    scenario = "dentist_moves_checkup"
    thursday = {"start_datetime": "day+3 07:45", "end_datetime": "day+3 08:30"}
    move = {
        "tool": "calendar__edit_calendar_event",
        "args": {"event_id": "ev-checkup-sam", "updates": thursday},
    }

    def email(cc: list[str]) -> dict[str, Any]:
        content = "Thursday at 07:45 works for me for the check-up. Sam"
        args = {"recipients": ["jo.rivera@home.example"], "cc": cc, "subject": "Dentist", "content": content}
        return {"tool": "email__send_email", "args": args}

    runs = _probe(
        scenario,
        _variant(
            "cc_practice",
            "pass",
            _with_actions(scenario, 0, [move, email(["reception@brightsmile.example"])]),
        ),
        _variant("someone_else", "fail", _with_actions(scenario, 0, [move, email([])]), "practice_told"),
    )
    assert runs["cc_practice"].ok, runs["cc_practice"].problems
    assert runs["someone_else"].ok, runs["someone_else"].problems


def test_probe_a_group_chat_that_includes_the_person_tells_them() -> None:
    scenario = "babysitter_for_anniversary_dinner"
    calendar = get_scenario(scenario).oracle.interventions[1].actions[0].model_dump(exclude_unset=True)

    def told(group: list[str]) -> list[dict[str, Any]]:
        content = "Sitter sorted: Zoe's coming Friday at 18:15"
        return [
            calendar,
            {"id": "grp", "tool": "messaging__create_group_conversation", "args": {"user_ids": group}},
            {
                "tool": "messaging__send_message_to_group_conversation",
                "args": {"conversation_id": "${grp.id}", "content": content},
            },
        ]

    runs = _probe(
        scenario,
        _variant("family_group", "pass", _with_actions(scenario, 1, told(["user-alex", "user-hana"]))),
        _variant(
            "no_alex", "fail", _with_actions(scenario, 1, told(["user-priya", "user-hana"])), "alex_told"
        ),
    )
    assert runs["family_group"].ok, runs["family_group"].problems
    assert runs["no_alex"].ok, runs["no_alex"].problems


def test_probe_a_forward_with_the_facts_tells_them() -> None:
    # the library's own variant: forwarding the studio's email dates the photo, but sends the print sheet
    runs = check_scenario(get_scenario("visa_centre_rejects_photo_resend_new_one"), runs=()).runs
    run = next(run for run in runs if run.run == "variant:forwards_studio_email")
    assert run.ok, run.problems


def test_probe_renamed_payslips_are_the_payslips_and_a_namesake_is_not() -> None:
    scenario = "accountant_asks_for_last_three_payslips"
    folder = "/Documents/Payslips/2025-26"
    text = (
        "Hi Rhona, my April, May (corrected) and June 2025 payslips. My gross salary is 44,200 pounds. Daniel"
    )

    def reply(paths: list[str]) -> dict[str, Any]:
        args = {"email_id": "email-rhona-payslips", "content": text, "attachments": paths}
        return {"tool": "email__reply_to_email", "args": args}

    months = {"apr_2025": "april", "may_2025_reissued": "may", "jun_2025": "june"}
    renamed = [
        {
            "tool": "files__copy_file",
            "args": {"source": f"{folder}/payslip_{m}.txt", "destination": f"/Shared/{n}"},
        }
        for m, n in months.items()
    ]
    other_april = "Brightwater Energy - payslip April 2024."
    namesake = {
        "tool": "files__write_file",
        "args": {"path": "/Shared/payslip_apr_2025.txt", "content": other_april},
    }
    wrong = ["/Shared/payslip_apr_2025.txt", *(f"{folder}/payslip_{m}.txt" for m in list(months)[1:])]
    runs = _probe(
        scenario,
        _variant(
            "renamed",
            "pass",
            _with_actions(scenario, 0, [*renamed, reply([f"/Shared/{n}" for n in months.values()])]),
        ),
        _variant(
            "namesake", "fail", _with_actions(scenario, 0, [namesake, reply(wrong)]), "latest_three_sent"
        ),
    )
    assert runs["renamed"].ok, runs["renamed"].problems
    assert runs["namesake"].ok, runs["namesake"].problems


def test_the_users_own_sends_on_the_screens_tell_too() -> None:
    by_user = {"action": {"actor": "user", "to": [ANN, "user-ann"], "args": {"content": {"contains": "hi"}}}}
    scenario = _scenario(by_user, TOLD_ANN)
    env = build_environment(scenario)
    env.advance_to(scenario.start.replace(minute=10))
    steps = [
        ("open_app", {"app_name": "email"}),
        ("open_email", {"email_id": "e_ann"}),
        ("reply", {"content": "Hi Ann"}),
        ("go_home", {}),
        ("open_app", {"app_name": "messaging"}),
        ("open_conversation", {"conversation_id": "conv-team"}),
        ("send_message", {"content": "Hi all"}),
    ]
    for tool, args in steps:
        assert env.call("user", tool, args).ok, tool
    outcome = evaluate(scenario, env.log.entries, env.snapshot(shared=True))
    assert outcome.goals[0].checks[0].detail.endswith("found 2")


def test_a_scenario_without_to_hashes_as_before_the_field_existed() -> None:
    # run folders made before 'to' and 'via' stay valid for scenarios that do not use them
    pattern = _scenario({"action": {"tool": "email__send_email"}}).goals[0].checks[0].action
    assert pattern is not None
    assert "to" not in pattern.model_dump() and "via" not in pattern.model_dump()
    told = _scenario({"action": {"to": ANN, "via": ["reply"]}}).goals[0].checks[0].action
    assert told is not None and told.model_dump()["via"] == ["reply"]


def test_who_a_send_reaches_is_to_cc_and_bcc_or_every_other_member() -> None:
    # the one notion side effects share with the checks
    email = {"recipients": ["Ann@x.example"], "cc": ["bob@x.example"], "bcc": ["cy@x.example"]}
    assert email_addressees(email) == ["Ann@x.example", "bob@x.example", "cy@x.example"]
    group = {"participant_ids": ["user-me", "user-ann", "user-bob"], "is_group": True}
    assert conversation_members(group, "user-me") == ["user-ann", "user-bob"]
    assert conversation_members({"participant_ids": ["user-me", "user-ann"]}, "user-me") == ["user-ann"]
