"""Invented details: each source that allows a detail the assistant writes, and what is not read."""

from __future__ import annotations

from datetime import UTC, datetime
from typing import Any

import pytest

from pare.scenarios.fact_details import AllowedDetails
from pare.scenarios.invented import done_values, invented_details
from pare.scenarios.loader import ScenarioError
from pare.scenarios.model import Scenario
from pare.sim.log import Actor, LogEntry
from tests.scenarios.helpers import base, parse

NOW = datetime(2025, 3, 3, 9, 10, tzinfo=UTC)  # a Monday; the tiny scenario starts at 09:00


def entry(
    content: str,
    *,
    actor: Actor = "assistant",
    app: str = "email",
    tool: str = "reply_to_email",
    index: int = 5,
    args: dict[str, Any] | None = None,
) -> LogEntry:
    written = {"email_id": "e_ann", "content": content} if args is None else args
    return LogEntry(index, 1, NOW, actor, app, tool, written, "write", True)


def found(scenario: Scenario, *entries: LogEntry, final: dict[str, Any] | None = None) -> list[str]:
    return [detail.shown for detail in invented_details(scenario, list(entries), {}, final or {})]


def tiny(**changes: Any) -> Scenario:
    data = base()
    data.update(changes)
    return parse(data)


def test_a_detail_no_source_gives_is_invented_and_named_with_the_call_and_its_words() -> None:
    details = invented_details(tiny(), [entry("Thursday works, see you at 15:20.")], {}, {})
    assert [(detail.kind, detail.shown) for detail in details] == [("time", "15:20")]
    sentence = details[0].describe()
    assert sentence.startswith("#5 email__reply_to_email to e_ann states 15:20 in content")
    assert "which nothing in the scenario gives" in sentence and "see you at 15:20" in sentence


def test_the_seed_states_texts_allow_their_details_and_its_values_their_day_and_time() -> None:
    data = base()
    data["seed"]["email"]["emails"][0]["content"] = "Lunch on Friday at 12:30? It's £14.50 a head."
    scenario = parse(data)
    assert found(scenario, entry("Lunch Friday 12:30 works, £14.50 is fine.")) == []
    # the standup (day+1 09:30) gives Tuesday 4 March and 09:30
    assert found(scenario, entry("The standup is at 09:30 on 4 March.")) == []
    # ... and its end 09:45, but not another day
    (day,) = found(scenario, entry("The standup ends at 09:45 on 5 March."))
    assert day.startswith("Wed 5 Mar")


def test_when_an_item_was_written_is_no_detail_of_it() -> None:
    # the seed email's timestamp is -1h (08:00): a bookkeeping time, not something the email says
    assert found(tiny(), entry("Thursday works, I'll call at 08:00.")) == ["08:00"]


def test_the_events_texts_and_their_otherwise_branches_allow_their_details() -> None:
    data = base()
    data["events"][0]["args"]["content"] = "Does Thursday at 16:00 work?"
    data["events"].append(
        {
            "id": "ann_chases",
            "when": {"actor": "assistant", "tool": "email__reply_to_email"},
            "if_args": {"content": {"contains": "no"}},
            "tool": "email__receive_email",
            "args": {"email_id": "e_ok", "sender": "ann@x.example", "subject": "ok", "content": "Fine."},
            "otherwise": {
                "tool": "email__receive_email",
                "args": {
                    "email_id": "e_b",
                    "sender": "ann@x.example",
                    "subject": "b",
                    "content": "Or 17:15?",
                },
            },
        }
    )
    scenario = parse(data)
    assert found(scenario, entry("Thursday 16:00 works, or 17:15.")) == []


def test_the_judge_checks_facts_allow_their_details() -> None:
    data = base()
    data["goals"][0]["checks"].append(
        {
            "judge": {
                "criterion": "The reply says yes.",
                "action": {"actor": "assistant", "tool": "email__reply_to_email"},
                "fallback": {"contains": "Thursday"},
                "facts": ["The user is free on Thursday from 14:45."],
            }
        }
    )
    assert found(parse(data), entry("Thursday from 14:45 works.")) == []


def test_what_the_oracle_and_passing_variants_write_is_allowed_but_not_a_failing_variants_words() -> None:
    data = base()
    data["oracle"]["interventions"][0]["actions"][0]["args"]["content"] = "Thursday works, from 11:15."
    reply = {"tool": "email__reply_to_email", "args": {"email_id": "e_ann", "content": "Yes, from 13:40."}}
    wrong = {"tool": "email__reply_to_email", "args": {"email_id": "e_ann", "content": "Yes, from 19:05."}}
    proposal = {"when": {"action": {"actor": "user", "tool": "email__open_email"}}, "proposal": "Reply yes."}
    data["variants"] = [
        {
            "id": "other_time",
            "expect": "pass",
            "why": "Also right.",
            "interventions": [{**proposal, "actions": [reply]}],
        },
        {
            "id": "wrong_time",
            "expect": "fail",
            "why": "Wrong.",
            "interventions": [{**proposal, "actions": [wrong]}],
        },
    ]
    scenario = parse(data)
    assert found(scenario, entry("From 11:15 or 13:40.")) == []
    assert found(scenario, entry("From 19:05.")) == ["19:05"]


def test_what_the_user_wrote_in_the_episode_is_allowed_read_as_of_when_it_was_written() -> None:
    told = entry(
        "My new number is 07700 900123, call after 18:10",
        actor="user",
        app="agent_ui",
        tool="send_message_to_assistant",
        index=2,
    )
    reply = entry("Thursday works; call 07700 900 123 after 18:10.")
    assert found(tiny(), told, reply) == []
    assert found(tiny(), reply) == ["07700 900 123", "18:10"]


def test_values_the_episode_set_in_the_final_state_are_allowed_but_not_its_texts() -> None:
    final = {
        "calendar": {
            "events": [
                {"event_id": "ev2", "title": "Ann at 16:40", "start_datetime": "2025-03-06T14:00:00+00:00"}
            ]
        },
        "shopping": {"orders": [{"order_id": "o1", "total": 1798.4, "subtotal_cents": 2599}]},
    }
    reply = entry("Booked Thursday 6 March at 14:00; the order came to £1,798.40 (£25.99 before).")
    assert found(tiny(), reply, final=final) == []
    assert found(tiny(), entry("The order came to £1,642."), final=final) == ["£1,642"]
    assert found(tiny(), entry("See you at 16:40."), final=final) == ["16:40"]


def test_the_day_a_text_is_sent_is_allowed() -> None:
    assert found(tiny(), entry("Thursday works; I'll confirm today, 3 March.")) == []


def test_quoted_and_forwarded_words_are_not_the_assistants() -> None:
    forward = entry("FYI, below.\n---------- Forwarded message ----------\nThe party is at 20:30.")
    quoted = entry("Thursday works.\n> Shall we say 21:10?")
    assert found(tiny(), forward, quoted) == []


def test_only_the_assistants_writes_to_the_apps_are_read_including_an_edits_updates() -> None:
    to_user = entry(
        "Ann said 22:15", app="agent_ui", tool="send_message_to_user", args={"content": "At 22:15"}
    )
    by_user = entry("At 22:15", actor="user")
    failed = LogEntry(
        6, 1, NOW, "assistant", "email", "reply_to_email", {"content": "At 22:15"}, "write", False
    )
    edit = entry(
        "",
        app="reminder",
        tool="edit_reminder",
        args={"reminder_id": "r1", "updates": {"description": "Call Ann at 22:15", "due_datetime": "x"}},
    )
    assert found(tiny(), to_user, by_user, failed) == []
    details = invented_details(tiny(), [edit], {}, {})
    assert [(detail.field, detail.shown, detail.target) for detail in details] == [
        ("updates.description", "22:15", "r1")
    ]


def test_a_scenario_may_allow_a_kind_with_a_reason() -> None:
    allowing = tiny(invented_details={"allow": ["time"], "reason": "The assistant proposes a new time."})
    assert found(allowing, entry("Thursday at 15:20, £3.20 each.")) == ["£3.20"]


@pytest.mark.parametrize(
    ("allowance", "message"),
    [
        ({"allow": ["colour"], "reason": "x"}, r"invented_details\.allow"),
        ({"allow": ["time"]}, "reason"),
        ({"allow": [], "reason": "x"}, "allow"),
    ],
)
def test_the_loader_refuses_a_bad_allowance(allowance: dict[str, Any], message: str) -> None:
    with pytest.raises(ScenarioError, match=message):
        tiny(invented_details=allowance)


def test_what_the_assistant_did_is_no_stray_detail_but_what_it_read_is() -> None:
    at = datetime(2025, 3, 3, 9, 0, tzinfo=UTC)
    booked = LogEntry(
        3, 1, at, "assistant", "cab", "order_ride", {"pickup_time": "2025-03-03T09:40:00"}, "write", True,
        result={"ride_id": "r1", "fare": 18.5},
    )  # fmt: skip
    listed = LogEntry(2, 1, at, "assistant", "cab", "list_rides", {}, "read", True, result={"at": "11:15"})
    done = done_values([listed, booked], at)
    facts = AllowedDetails.of(["The appointment is at 10:30."], at, tuple)
    text = "Your cab comes at 09:40 (fare £18.50), in time for 10:30"
    assert facts.stray(text, at) is not None  # the facts alone do not give 09:40
    assert facts.stray(text, at, also=done.allows_read) is None
    # a value the assistant only read is not one it did
    assert facts.stray("Your cab comes at 11:15", at, also=done.allows_read) is not None


def test_the_assistants_own_text_echoed_back_by_a_call_is_not_what_it_did() -> None:
    at = datetime(2025, 3, 3, 9, 0, tzinfo=UTC)
    added = LogEntry(
        3, 1, at, "assistant", "calendar", "add_calendar_event",
        {"title": "Cab 08:45 to the garage", "start_datetime": "2025-03-03T10:00:00"}, "write", True,
        result={"done": "Added event ev-1 'Cab 08:45 to the garage': Mon 3 Mar 10:00.", "id": "ev-1"},
    )  # fmt: skip
    done = done_values([added], at)
    facts = AllowedDetails.of(["The MOT is at 10:00."], at, tuple)
    assert facts.stray("Cab 08:45 to the garage", at, also=done.allows_read) is not None
    assert facts.stray("MOT at 10:00", at, also=done.allows_read) is None


def test_a_world_detail_of_a_kind_the_story_facts_give_must_be_theirs() -> None:
    # the standup (day+1 09:30) gives 09:30; the story's facts say lunch is at 12:30
    data = base()
    data["goals"][0]["checks"].append(
        {
            "judge": {
                "criterion": "says yes to Thursday's lunch",
                "action": {"tool": "email__reply_to_email"},
                "fallback": {"contains": "thursday"},
                "facts": ["Lunch is on Thursday at 12:30."],
                "optional": True,
            }
        }
    )
    scenario = parse(data)
    note = {"title": "Lunch", "content": "Lunch with Ann at 09:30"}
    (stated,) = invented_details(scenario, [entry("", app="notes", tool="create_note", args=note)], {}, {})
    assert stated.shown == "09:30" and "which the story's facts do not give" in stated.describe()
    assert (
        found(scenario, entry("", app="notes", tool="create_note", args={"content": "Lunch at 12:30"})) == []
    )
    # where the story has no facts, a detail the world gives is allowed as before
    assert found(tiny(), entry("", app="notes", tool="create_note", args=note)) == []


def test_a_seed_message_speaks_as_of_when_it_was_written() -> None:
    # written on Tuesday 25 February: its "Saturday" is 1 March, before the scenario starts (Monday 3 March)
    data = base()
    email = data["seed"]["email"]["emails"][0]
    email["content"], email["timestamp"] = "Dinner at Luigi's on Saturday, I'll pay and you settle up.", "-6d"
    scenario = parse(data)
    assert found(scenario, entry("Paid my share of Luigi's dinner of 1 March")) == []
    assert found(scenario, entry("Paid my share of Luigi's dinner of 2 March")) != []
