"""What a solution tells a person must be read by a judge check; an optional judge check reads a courtesy
message that some solutions send and others do not.

The side-effect envelope licenses sending to a person by shape alone, so once a passing solution messages
Bob, a false message to Bob is inside it: these tests pin the two halves of the repair (the optional check
that rejects the false text, and the gate's list of sends no judge check reads).
"""

from __future__ import annotations

from typing import Any

import pytest

from pare.env import Environment
from pare.errors import UserInputError
from pare.scenarios import Scenario
from pare.scenarios.build import build_environment
from pare.scenarios.checks import evaluate
from pare.scenarios.model import JudgeCheck
from pare.scenarios.unjudged import unjudged_events, unread_sends
from tests.scenarios.helpers import base, parse

ANN = "ann@x.example"
TOLD_ANN = {
    "judge": {
        "criterion": "Ann is told Thursday works.",
        "action": {"to": [ANN, "user-ann"]},
        "fallback": {"affirms": "thursday"},
    }
}
BOB_TOLD_TRULY = {
    "judge": {
        "criterion": "What Bob is told is true: lunch is on Thursday, not Friday.",
        "action": {"to": "user-bob"},
        "optional": True,
        "fallback": {"not": {"mentions_day": "day+4"}},
    }
}
TO_ANN = ("email__reply_to_email", {"email_id": "e_ann", "content": "Thursday works."})
TRUE_TO_BOB = (
    "messaging__send_message",
    {"user_id": "user-bob", "content": "Lunch with Ann is on Thursday."},
)
FALSE_TO_BOB = ("messaging__send_message", {"user_id": "user-bob", "content": "Lunch with Ann is on Friday."})


def _scenario(*checks: dict[str, Any]) -> Scenario:
    """The tiny scenario with a chat with Bob, and one goal holding ``checks``."""
    data = base()
    data["apps"] = ["email", "calendar", "messaging"]
    data["seed"]["messaging"] = {
        "users": {"user-me": "Me", "user-ann": "Ann", "user-bob": "Bob"},
        "conversations": [{"conversation_id": "conv-bob", "participant_ids": ["user-me", "user-bob"]}],
    }
    data["goals"] = [{"id": "told", "description": "Ann knows.", "checks": list(checks)}]
    return parse(data)


def _played(scenario: Scenario, *calls: tuple[str, dict[str, Any]]) -> tuple[Environment, bool]:
    """The world after the assistant's ``calls``, and whether the goal was met."""
    env = build_environment(scenario)
    env.advance_to(scenario.start.replace(minute=10))  # Ann's email has arrived
    for tool, args in calls:
        result = env.call("assistant", tool, args, mode="execute")
        assert result.ok, result.error
    outcome = evaluate(scenario, env.log.entries, env.snapshot(shared=True), attribution=env.attribution)
    return env, outcome.success


def test_an_optional_judge_check_holds_when_nothing_is_sent_and_rejects_a_false_text() -> None:
    scenario = _scenario(TOLD_ANN, BOB_TOLD_TRULY)
    assert _played(scenario, TO_ANN)[1]  # Bob need not be told
    assert _played(scenario, TO_ANN, TRUE_TO_BOB)[1]
    assert not _played(scenario, TO_ANN, FALSE_TO_BOB)[1]


def test_a_goal_with_only_an_optional_judge_check_is_refused() -> None:
    with pytest.raises(UserInputError, match="no positive check"):
        _scenario(BOB_TOLD_TRULY)


def test_a_judge_check_that_is_not_optional_dumps_as_before() -> None:
    check = JudgeCheck.model_validate(TOLD_ANN["judge"])
    assert "optional" not in check.model_dump()  # the content hash of every older scenario is unchanged
    assert JudgeCheck.model_validate(BOB_TOLD_TRULY["judge"]).model_dump()["optional"] is True


def _unread(scenario: Scenario, *calls: tuple[str, dict[str, Any]]) -> list[str]:
    env, _ = _played(scenario, *calls)
    return list(unread_sends(scenario, env.log.entries, env.snapshot(shared=True)))


def test_a_message_no_judge_check_reads_is_named_with_whom_it_reached() -> None:
    unread = _unread(_scenario(TOLD_ANN), TO_ANN, TRUE_TO_BOB)
    assert len(unread) == 1  # the reply to Ann is read by the goal; the message to Bob by nothing
    assert "user-bob" in unread[0] and "messaging__send_message" in unread[0]


def test_a_message_an_optional_judge_check_reads_is_not_named() -> None:
    assert _unread(_scenario(TOLD_ANN, BOB_TOLD_TRULY), TO_ANN, TRUE_TO_BOB) == []


def test_what_goes_to_the_user_alone_is_never_named() -> None:
    to_me = ("email__send_email", {"recipients": ["me@pare.example"], "subject": "Note", "content": "Thu."})
    assert _unread(_scenario(TOLD_ANN), TO_ANN, to_me) == []


def test_the_gate_warns_about_a_passing_variants_message_no_judge_check_reads() -> None:
    from pare.bench.selftest import check_scenario

    data = base()
    data["apps"] = ["email", "calendar", "messaging"]
    data["seed"]["messaging"] = {
        "users": {"user-me": "Me", "user-bob": "Bob"},
        "conversations": [{"conversation_id": "conv-bob", "participant_ids": ["user-me", "user-bob"]}],
    }
    reply = data["oracle"]["interventions"][0]
    tells_bob = {
        "tool": "messaging__send_message",
        "args": {"user_id": "user-bob", "content": "Lunch is on."},
    }
    data["variants"] = [
        {
            "id": "and_bob",
            "expect": "pass",
            "why": "Bob may know.",
            "interventions": [{**reply, "actions": [*reply["actions"], tells_bob]}],
        }
    ]
    verdict = check_scenario(parse(data), runs=("oracle",))
    to_bob = [line for line in verdict.unread_sends if "user-bob" in line]
    assert len(to_bob) == 1 and to_bob[0].startswith("[variant:and_bob]")
    assert verdict.run("variant:and_bob").ok  # the variant is judged right; what nothing reads is a breach
    assert not verdict.ok and any("unread send [variant:and_bob]" in line for line in verdict.breaches())
    assert not any("user-bob" in line for line in verdict.warnings)


def test_a_reactive_event_on_free_text_without_a_judge_is_named_and_one_with_a_judge_is_not() -> None:
    reaction = {
        "id": "ann_answers",
        "when": {"to": ANN},
        "if_args": {"content": {"affirms": "thursday"}},
        "tool": "email__receive_email",
        "args": {"email_id": "e_yes", "sender": ANN, "subject": "Re", "content": "Great!"},
    }
    data = base()
    data["events"].append(reaction)
    assert [line for line in unjudged_events(parse(data)) if "'ann_answers'" in line and "content" in line]
    data["events"][-1] = {**reaction, "judge": {"criterion": "The email says Thursday works."}}
    assert list(unjudged_events(parse(data))) == []


def test_a_forward_without_words_of_its_own_is_not_named() -> None:
    forward = ("email__forward_email", {"email_id": "e_ann", "recipients": ["bob@x.example"]})
    assert _unread(_scenario(TOLD_ANN), TO_ANN, forward) == []


def test_a_text_field_no_check_reads_is_named_and_one_read_by_text_is_not() -> None:
    from pare.scenarios.unjudged import unread_fields

    event = (
        "calendar__add_calendar_event",
        {
            "title": "Lunch with Ann",
            "start_datetime": "2025-03-06T12:30:00Z",
            "end_datetime": "2025-03-06T13:30:00Z",
            "location": "Luigi's",
        },
    )
    at_the_time = {"state": {"path": "calendar.events", "where": {"start_datetime": "day+3 12:30"}}}
    env, _ = _played(_scenario(TOLD_ANN, at_the_time), TO_ANN, event)
    named = list(unread_fields(_scenario(TOLD_ANN, at_the_time), env.log.entries))
    assert {line.split("'")[1] for line in named} == {"title", "location"}
    by_text = {"state": {"path": "calendar.events", "where": {"_text": {"contains": "lunch"}}}}
    assert list(unread_fields(_scenario(TOLD_ANN, by_text), env.log.entries)) == []


def test_an_optional_judge_checks_sentence_says_it_holds_without_a_text() -> None:
    from pare.scenarios.checks import check_sentences

    sentences = check_sentences(_scenario(TOLD_ANN, BOB_TOLD_TRULY))["told"]
    assert "if there is one" in sentences[1] and "if there is one" not in sentences[0]
