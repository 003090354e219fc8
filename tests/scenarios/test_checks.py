"""Checks evaluated on real episodes of the tiny scenario."""

from __future__ import annotations

import asyncio
import re
from collections.abc import Sequence
from typing import Any

import pytest

from pare.agents import SilentAssistant, SilentUser
from pare.bench import run_episode
from pare.errors import ProviderUnavailable
from pare.scenarios import OracleAssistant, OracleUser, evaluate
from pare.scenarios.checks import JudgeVerdict, aevaluate
from tests.scenarios.helpers import base, parse


def _oracle_run(data: dict[str, Any]) -> Any:
    scenario = parse(data)
    return scenario, run_episode(scenario, OracleUser(scenario), OracleAssistant(scenario))


REPLIED = {"action": {"tool": "email__reply_to_email"}}
"""A check the oracle meets, so every goal has a positive check on the assistant's work."""


def _with_checks(*checks: dict[str, Any]) -> dict[str, Any]:
    data = base()
    data["goals"] = [{"id": "g", "description": "goal", "checks": [REPLIED, *checks]}]
    return data


def test_oracle_meets_the_goal_and_silence_does_not() -> None:
    scenario, result = _oracle_run(base())
    assert result.success
    silent = run_episode(scenario, SilentUser(), SilentAssistant())
    assert not silent.success
    (failure,) = silent.outcome.failures()
    assert "wanted at least 1 assistant email__reply_to_email" in failure.detail


def test_action_count_and_near_misses_are_reported() -> None:
    data = _with_checks({"action": {"tool": "email__reply_to_email", "count": 2}})
    _, result = _oracle_run(data)
    (failure,) = result.outcome.failures()
    assert "wanted exactly 2" in failure.detail and "found 1" in failure.detail
    data = _with_checks(
        {"action": {"tool": "email__reply_to_email", "args": {"content": {"contains": "friday"}}}}
    )
    _, result = _oracle_run(data)
    assert "other calls to that tool: #" in result.outcome.failures()[0].detail


def test_no_action_names_the_forbidden_call() -> None:
    data = _with_checks({"no_action": {"app": "email", "kind": "write"}})
    _, result = _oracle_run(data)
    (failure,) = result.outcome.failures()
    assert (
        failure.form == "no_action" and "forbidden" in failure.detail and "reply_to_email" in failure.detail
    )


def test_actor_any_and_user_actions() -> None:
    data = _with_checks(
        {"action": {"actor": "user", "tool": "email__open_email", "args": {"email_id": "e_ann"}}},
        {"action": {"actor": "any", "tool": "system__open_app"}},
        {"action": {"actor": "env", "tool": "email__receive_email", "result": "e_ann"}},
        {"action": {"app": "email", "kind": "write", "args": {"email_id": "e_ann"}}},
    )
    _, result = _oracle_run(data)
    assert result.success, result.outcome.failures()


def test_after_and_before_event() -> None:
    data = _with_checks(
        {"action": {"tool": "email__reply_to_email", "after_event": "ann_asks"}},
        {"no_action": {"actor": "user", "tool": "system__open_app", "before_event": "ann_asks"}},
    )
    _, result = _oracle_run(data)
    assert result.success, result.outcome.failures()
    data = _with_checks({"action": {"tool": "email__reply_to_email", "before_event": "ann_asks"}})
    _, result = _oracle_run(data)
    assert not result.success


def test_state_checks_with_where_count_and_value() -> None:
    data = _with_checks(
        {
            "state": {
                "path": "email.emails",
                "where": {"folder": "SENT", "recipients": {"contains": "ann@x.example"}},
                "count": 1,
            }
        },
        {"state": {"path": "email.user_email", "value": "me@pare.example"}},
        {"state": {"path": "calendar.events", "where": {"title": "Standup"}, "count": {"min": 1, "max": 1}}},
    )
    _, result = _oracle_run(data)
    assert result.success, result.outcome.failures()
    data = _with_checks({"state": {"path": "email.emails", "where": {"folder": "SENT"}, "count": 0}})
    _, result = _oracle_run(data)
    (failure,) = result.outcome.failures()
    assert "1 of 3 items match" in failure.detail and "wanted exactly 0" in failure.detail


def test_state_check_on_missing_path_and_non_collection() -> None:
    _, result = _oracle_run(base())
    data = _with_checks({"state": {"path": "email.emails.nope"}})
    outcome = evaluate(parse(data), result.env.log.entries, result.env.snapshot())
    assert "does not exist" in outcome.failures()[0].detail
    data = _with_checks({"state": {"path": "email.user_email", "where": {"x": 1}}})
    outcome = evaluate(parse(data), result.env.log.entries, result.env.snapshot())
    assert "not a collection" in outcome.failures()[0].detail


def test_judge_uses_the_model_when_given_and_the_fallback_otherwise() -> None:
    data = _with_checks(
        {
            "judge": {
                "criterion": "says yes to Thursday",
                "action": {"tool": "email__reply_to_email"},
                "fallback": {"contains": "thursday"},
            }
        }
    )
    scenario, result = _oracle_run(data)
    assert result.success
    assert "no judge model; fallback" in result.outcome.goals[0].checks[-1].detail
    seen: list[tuple[str, str, Sequence[str]]] = []

    async def strict_judge(criterion: str, text: str, facts: Sequence[str] = ()) -> JudgeVerdict:
        seen.append((criterion, text, facts))
        return JudgeVerdict(False, "It does not name a time.")

    outcome = asyncio.run(
        aevaluate(scenario, result.env.log.entries, result.env.snapshot(), judge=strict_judge)
    )
    assert not outcome.success and seen == [("says yes to Thursday", "Thursday works!", ())]
    assert outcome.failures()[0].detail.endswith(" | the judge: It does not name a time.")


def test_an_optional_judge_holds_when_nothing_is_sent_and_reads_what_is() -> None:
    def optional(fallback: dict[str, Any], tool: str) -> dict[str, Any]:
        judge = {"criterion": "is true", "action": {"tool": tool}, "fallback": fallback, "optional": True}
        return {"judge": judge}

    # nothing sent with that tool: nothing false was said
    _, result = _oracle_run(_with_checks(optional({"contains": "friday"}, "email__send_email")))
    assert result.success
    assert "(optional): nothing to judge" in result.outcome.goals[0].checks[-1].detail
    # the oracle's reply is sent: it is judged as ever
    _, result = _oracle_run(_with_checks(optional({"contains": "friday"}, "email__reply_to_email")))
    assert not result.success
    _, result = _oracle_run(_with_checks(optional({"contains": "thursday"}, "email__reply_to_email")))
    assert result.success


def test_a_question_two_judge_checks_share_is_asked_once_and_a_failed_call_raises_as_itself() -> None:
    judged = {
        "criterion": "says yes to Thursday",
        "action": {"tool": "email__reply_to_email"},
        "fallback": {"contains": "thursday"},
    }
    scenario, result = _oracle_run(_with_checks({"judge": judged}, {"judge": judged, "description": "again"}))
    asked: list[str] = []

    async def agreeing(criterion: str, text: str, facts: Sequence[str] = ()) -> JudgeVerdict:
        asked.append(text)
        await asyncio.sleep(0)  # both checks wait on the one call
        return JudgeVerdict(True, "It says yes.", "YES. It says yes.", "judge-model")

    log, state = result.env.log.entries, result.env.snapshot()
    outcome = asyncio.run(aevaluate(scenario, log, state, judge=agreeing))
    assert outcome.success and asked == ["Thursday works!"]
    for check in outcome.goals[0].checks[1:]:
        (judged_text,) = check.judged
        assert (
            judged_text.verdict.answer == "YES. It says yes." and judged_text.verdict.model == "judge-model"
        )
    assert outcome.goals[0].checks[0].judged == ()  # not a judge check

    async def down(criterion: str, text: str, facts: Sequence[str] = ()) -> JudgeVerdict:
        raise ProviderUnavailable("the judge's provider is down")

    with pytest.raises(ProviderUnavailable, match="provider is down"):
        asyncio.run(aevaluate(scenario, log, state, judge=down))


def test_per_goal_results_and_goal_rate() -> None:
    data = base()
    data["goals"].append(
        {"id": "never", "description": "impossible", "checks": [{"action": {"tool": "email__delete_email"}}]}
    )
    _, result = _oracle_run(data)
    assert not result.success
    assert [goal.passed for goal in result.outcome.goals] == [True, False]
    assert result.outcome.goal_rate == 0.5
    assert result.outcome.to_dict()["goals"][1]["id"] == "never"


def test_a_list_of_tools_means_any_of_them() -> None:
    """A reply or a fresh email: one pattern, each tool's arguments read as missing by the other."""
    either = ["email__send_email", "email__reply_to_email"]
    _, result = _oracle_run(
        _with_checks({"action": {"tool": either, "args": {"content": {"contains": "thursday"}}}})
    )
    assert result.success
    _, result = _oracle_run(_with_checks({"no_action": {"tool": ["email__send_email", "email__save_draft"]}}))
    assert result.success
    _, result = _oracle_run(_with_checks({"no_action": {"tool": either}}))
    (failure,) = result.outcome.failures()
    assert "email__send_email or email__reply_to_email" in failure.detail


def test_a_list_of_tools_is_checked_tool_by_tool() -> None:
    from pare.scenarios import ScenarioError

    data = _with_checks({"action": {"tool": ["email__send_email", "email__reply_too"]}})
    try:
        parse(data)
    except ScenarioError as error:
        found = [str(problem) for problem in error.problems]
    else:
        raise AssertionError("an unknown tool in a list was accepted")
    assert any("tool[1]" in problem and "email__reply_too" in problem for problem in found), found
    data = _with_checks(
        {"action": {"tool": ["email__send_email", "email__reply_to_email"], "args": {"colour": 1}}}
    )
    try:
        parse(data)
    except ScenarioError as error:
        assert "has no argument 'colour'" in str(error)
    else:
        raise AssertionError("an argument no listed tool takes was accepted")


def test_a_judge_reads_every_matched_text_alone_or_together() -> None:
    """An answer split over two replies: judged alone, neither part is the whole answer; ``together``
    reads them as one."""
    data = _with_checks()
    data["oracle"]["interventions"][0]["actions"].append(
        {"tool": "email__reply_to_email", "args": {"email_id": "e_ann", "content": "See you at 10."}}
    )
    judged = {
        "criterion": "Confirms Thursday at 10.",
        "action": {"tool": "email__reply_to_email"},
        "fallback": {"mentions_day": "day+3", "mentions_clock": "10:00"},
    }
    data["goals"][0]["checks"].append({"judge": judged})
    _, alone = _oracle_run(data)
    assert not alone.success
    data["goals"][0]["checks"][-1] = {"judge": {**judged, "together": True}}
    _, together = _oracle_run(data)
    assert together.success, together.outcome.failures()


def test_a_user_action_is_matched_by_the_screen_it_was_made_on() -> None:
    """A screen action carries only what the user typed; the screen says which item it acted on."""
    on_inbox = {"actor": "user", "tool": "email__open_email", "screen": {"contains": "INBOX"}}
    _, result = _oracle_run(_with_checks({"action": on_inbox}))
    assert result.success
    on_sent = {**on_inbox, "screen": {"contains": "SENT"}}
    _, result = _oracle_run(_with_checks({"action": on_sent}))
    (failure,) = result.outcome.failures()
    assert "on a screen contains ['sent']" in failure.detail


def test_screen_is_refused_on_the_assistants_patterns() -> None:
    from pare.scenarios import ScenarioError

    data = _with_checks({"action": {"tool": "email__reply_to_email", "screen": {"contains": "INBOX"}}})
    try:
        parse(data)
    except ScenarioError as error:
        assert "'screen' is where the user was when acting" in str(error)
    else:
        raise AssertionError("screen on an assistant pattern was accepted")


def test_goals_met_agrees_with_evaluate_and_snapshots_only_when_a_state_check_is_reached() -> None:
    """The end-when-met check stops at the first failing check; the state is taken only if needed."""
    from pare.scenarios.checks import goals_met

    data = _with_checks({"state": {"path": "email.emails", "where": {"folder": "SENT"}, "count": 1}})
    scenario, result = _oracle_run(data)
    log, env = result.env.log.entries, result.env
    assert goals_met(scenario, log, env.snapshot(), attribution=env.attribution) is result.success is True
    taken: list[bool] = []

    def snapshot() -> dict[str, Any]:
        taken.append(True)
        return env.snapshot()

    assert goals_met(scenario, log, snapshot, attribution=env.attribution) and taken == [True]
    silent = run_episode(scenario, SilentUser(), SilentAssistant())
    taken.clear()
    assert not goals_met(scenario, silent.env.log.entries, snapshot) and not silent.success
    assert taken == []  # the reply was never sent: no state check was reached


def test_a_changed_copy_of_a_scenario_is_judged_by_its_own_checks() -> None:
    """Checks are compiled once per scenario object; a copy with other goals is another object."""
    scenario, result = _oracle_run(_with_checks())
    never = parse(_with_checks({"action": {"tool": "email__delete_email"}})).goals
    changed = scenario.model_copy(update={"goals": never})
    log, state = result.env.log.entries, result.env.snapshot()
    assert evaluate(scenario, log, state).success
    assert not evaluate(changed, log, state).success
    assert evaluate(scenario, log, state).success


def test_the_user_doing_the_work_is_told_apart_from_the_assistant_not_doing_it() -> None:
    """A failing check on the assistant's work is read again crediting the user, on the same state."""
    data = _with_checks(
        {"state": {"path": "calendar.events", "where": {"title": "Standup"}, "by": "assistant"}}
    )
    scenario, result = _oracle_run(data)
    outcome = evaluate(
        scenario, result.env.log.entries, result.env.snapshot(), attribution=result.env.attribution
    )
    (failure,) = outcome.failures()
    assert not failure.user_made and "0 of them made by the assistant" in failure.detail


def test_a_pattern_is_compiled_once_per_pattern_and_start() -> None:
    """Episodes share a scenario's compiled patterns; another start compiles it again."""
    from datetime import UTC, datetime

    from pare.scenarios.patterns import CompiledPattern

    scenario = parse(base())
    check = scenario.goals[0].checks[0].action
    assert check is not None
    first = CompiledPattern.of(check, scenario.start)
    assert CompiledPattern.of(check, scenario.start) is first
    other = datetime(2030, 1, 1, tzinfo=UTC)
    assert CompiledPattern.of(check, other).start is other


def test_a_failing_fallback_quotes_the_text_and_says_which_clause_failed() -> None:
    judged = {
        "judge": {
            "criterion": "says yes to Friday",
            "action": {"tool": "email__reply_to_email"},
            "fallback": {"any_of": [{"affirms": "friday"}, {"affirms": "thursday", "contains": "friday"}]},
        }
    }
    data = _with_checks(judged)
    data["oracle"]["interventions"][0]["actions"][0]["args"]["content"] = "Not Friday as Thursday works!"
    _, result = _oracle_run(data)
    (failure,) = result.outcome.failures()
    assert failure.detail.startswith("no judge model; fallback any of (")
    assert re.search(
        r'fails on 1 text\(s\) \(#\d+\): "Not Friday as Thursday works!": any of: none holds \(',
        failure.detail,
    )
    clause = 'clause "Not Friday as Thursday works"'
    assert f"affirms 'friday': found 'Friday' in {clause} but it is negated by 'Not'" in failure.detail
    assert "contains 'friday'" not in failure.detail  # the part of the rule that held is not blamed


def test_a_failing_state_value_and_a_near_call_say_why() -> None:
    data = _with_checks({"state": {"path": "email.user_email", "value": {"contains": "bob"}}})
    _, result = _oracle_run(data)
    assert "'bob' is not in the text as a whole word" in result.outcome.failures()[0].detail
    data = _with_checks(
        {"action": {"tool": "email__reply_to_email", "args": {"content": {"affirms": "friday"}}}}
    )
    _, result = _oracle_run(data)
    detail = result.outcome.failures()[0].detail
    assert "does not match: content: affirms 'friday': 'friday' is not in the text as a whole word" in detail


def test_the_verdict_alone_is_not_explained(monkeypatch: Any) -> None:
    from pare.scenarios import checks, explain

    def refuse(*args: Any) -> str:
        raise AssertionError("explained")

    data = _with_checks({"state": {"path": "email.user_email", "value": {"contains": "bob"}}})
    scenario, result = _oracle_run(data)
    monkeypatch.setattr(explain, "explain", refuse)
    assert not checks.goals_met(scenario, result.env.log.entries, result.env.snapshot())


def test_a_judge_reads_a_field_an_edit_sets_inside_its_updates() -> None:
    from pare.scenarios.checks import judged_text

    edit = {"reminder_id": "rem-1", "updates": {"description": "Twice a day", "title": "Exercises"}}
    assert judged_text(edit, "description") == "Twice a day"  # update_reminder's new description
    assert judged_text({"description": "Daily", "updates": {"description": "x"}}, "description") == "Daily"
    assert judged_text({"updates": {"due_datetime": "2025-06-01"}}, "description") is None
    assert judged_text({"content": None}, "content") is None


def test_an_items_days_are_read_as_of_when_it_was_written() -> None:
    from datetime import timedelta

    from pare.env.attribution import Attribution
    from pare.sim.log import LogEntry

    data = _with_checks(
        {"state": {"path": "calendar.events", "where": {"description": {"mentions_day": "day+3"}}}}
    )
    scenario, result = _oracle_run(data)
    state = result.env.snapshot()
    event = {"event_id": "ev-note", "title": "Bins", "description": "Put the bins out tomorrow",
             "start_datetime": "2025-03-06T19:00:00Z", "end_datetime": "2025-03-06T19:15:00Z"}  # fmt: skip
    before = state["calendar"]
    after = {**before, "events": {**before["events"], "ev-note": event}}
    state = {**state, "calendar": after}
    written = scenario.start + timedelta(days=2)  # on day+2: its "tomorrow" is day+3
    entry = LogEntry(
        index=len(result.env.log.entries), turn=9, time=written, actor="assistant", app="calendar",
        tool="add_calendar_event", args={}, kind="write", ok=True,
    )  # fmt: skip
    attribution = Attribution()
    attribution.record("assistant", entry.index, "calendar", before, after)
    log = [*result.env.log.entries, entry]
    assert evaluate(scenario, log, state, attribution=attribution).goals[0].passed
    unattributed = evaluate(scenario, log, state, attribution=Attribution())  # read as of the start
    assert not unattributed.goals[0].passed


def test_any_of_holds_when_one_way_holds_with_all_its_checks() -> None:
    thursday = {"action": {"tool": "email__reply_to_email", "args": {"content": {"contains": "thursday"}}}}
    friday = {"action": {"tool": "email__reply_to_email", "args": {"content": {"contains": "friday"}}}}
    fresh = {"action": {"tool": "email__send_email"}}
    _, result = _oracle_run(_with_checks({"any_of": [{"all_of": [fresh]}, {"all_of": [REPLIED, thursday]}]}))
    assert result.success
    assert "way 2 of 2 holds" in result.outcome.goals[0].checks[-1].detail
    _, result = _oracle_run(_with_checks({"any_of": [{"all_of": [fresh]}, {"all_of": [REPLIED, friday]}]}))
    assert not result.success
    detail = result.outcome.goals[0].checks[-1].detail
    assert detail.startswith("no way holds: way 1: ") and "way 2: " in detail


@pytest.mark.parametrize(
    ("checks", "message"),
    [
        ([{"all_of": [REPLIED]}], "at least two ways"),
        (
            [
                {"all_of": [REPLIED]},
                {
                    "all_of": [
                        {
                            "judge": {
                                "criterion": "c",
                                "action": {"tool": "email__reply_to_email"},
                                "fallback": {"contains": "x"},
                            }
                        }
                    ]
                },
            ],
            "cannot stand inside 'any_of'",
        ),
        (
            [{"all_of": [REPLIED]}, {"all_of": [{"action": {"tool": "email__reply_to_emial"}}]}],
            "reply_to_emial",
        ),
    ],
)
def test_any_of_is_checked_at_load_like_its_checks(checks: list[dict[str, Any]], message: str) -> None:
    from pare.scenarios.loader import ScenarioError

    with pytest.raises((ScenarioError, ValueError), match=message):
        parse(_with_checks({"any_of": checks}))


def test_fields_read_inside_any_of_count_as_read() -> None:
    from pare.scenarios.unjudged import _fields_read

    inside = {"state": {"path": "calendar.events", "where": {"location": {"contains": "hall"}}, "count": 0}}
    scenario = parse(_with_checks({"any_of": [{"all_of": [REPLIED]}, {"all_of": [inside]}]}))
    assert "location" in _fields_read(scenario)["calendar"]
