"""The model judge: a strict verdict, a one-sentence reason kept with the check, and the scenario's facts."""

from __future__ import annotations

from typing import Any

import pytest

from pare.agents.judge import ModelJudge, read_verdict
from pare.agents.scripted import ScriptedModel
from pare.bench import run_episode
from pare.scenarios import OracleAssistant, OracleUser, ScenarioError
from tests.scenarios.helpers import base, parse

FACTS = ["Ann's dinner is on Thursday at 19:00.", "It is at Luigi's on Mill Road."]


def _judged(**extra: Any) -> dict[str, Any]:
    data = base()
    data["goals"][0]["checks"] = [
        {
            "judge": {
                "criterion": "accepts Thursday",
                "action": {"tool": "email__reply_to_email"},
                "fallback": {"contains": "thursday"},
                **extra,
            }
        }
    ]
    return data


@pytest.mark.parametrize(
    ("answer", "passed", "reason"),
    [
        ("YES\nThe reply accepts Thursday.", True, "The reply accepts Thursday."),
        ("Yes, it does.", True, "it does."),
        ("NO - it names Friday instead.", False, "it names Friday instead."),
        ("no:\n  it gives\n a time nobody  said.", False, "it gives a time nobody said."),
        ("Probably yes; it is warm.", False, "Probably yes; it is warm."),
        ("Verdict: YES", False, "Verdict: YES"),
        ("", False, ""),
    ],
)
def test_only_a_clear_yes_passes_and_the_rest_is_the_reason(answer: str, passed: bool, reason: str) -> None:
    verdict = read_verdict(answer)
    assert (verdict.passed, verdict.reason) == (passed, reason)


def test_a_long_reason_is_cut() -> None:
    verdict = read_verdict("NO. " + "word " * 200)
    assert not verdict.passed and len(verdict.reason) <= 300 and verdict.reason.endswith("...")


def test_the_reason_is_kept_in_the_checks_detail_and_the_trajectory() -> None:
    scenario = parse(_judged())
    judge = ModelJudge(ScriptedModel(["YES\nIt says Thursday works."]))
    result = run_episode(scenario, OracleUser(scenario), OracleAssistant(scenario), judge=judge)
    assert result.success
    check = result.to_dict()["outcome"]["goals"][0]["checks"][0]
    assert check["detail"].endswith(" | the judge: It says Thursday works.")


def test_the_facts_go_to_the_judge_and_without_them_the_prompt_has_none() -> None:
    scenario = parse(_judged(facts=FACTS))
    model = ScriptedModel(["NO\nThe reply does not say Luigi's."])
    result = run_episode(scenario, OracleUser(scenario), OracleAssistant(scenario), judge=ModelJudge(model))
    assert not result.success
    question = model.requests[0][1].content or ""
    assert "Facts:\n- Ann's dinner is on Thursday at 19:00.\n- It is at Luigi's on Mill Road.\n" in question
    assert question.index("Criterion:") < question.index("Facts:") < question.index("Text:\nThursday works!")
    plain = parse(_judged())
    bare = ScriptedModel(["YES"])
    run_episode(plain, OracleUser(plain), OracleAssistant(plain), judge=ModelJudge(bare))
    assert "Facts" not in (bare.requests[0][1].content or "")


def test_every_rejected_text_says_why_and_an_accepted_one_ends_the_judging() -> None:
    data = _judged()
    data["oracle"]["interventions"][0]["actions"].append(
        {"tool": "email__reply_to_email", "args": {"email_id": "e_ann", "content": "See you then."}}
    )
    scenario = parse(data)
    rejected = ModelJudge(ScriptedModel(["NO. It names no day.", "NO. It names no day either."]))
    result = run_episode(scenario, OracleUser(scenario), OracleAssistant(scenario), judge=rejected)
    (failure,) = result.outcome.failures()
    assert failure.detail.endswith(" | the judge: It names no day. | the judge: It names no day either.")
    accepting = ScriptedModel(["YES. It accepts Thursday."])
    judge = ModelJudge(accepting)
    result = run_episode(scenario, OracleUser(scenario), OracleAssistant(scenario), judge=judge)
    assert result.success and len(accepting.requests) == 1


@pytest.mark.parametrize(
    ("facts", "problem"),
    [
        (["Dinner is at 19:00.", "  "], "facts[1] is empty"),
        (["Dinner is at 19:00.", "dinner is at 19:00. "], "facts[1] repeats an earlier fact"),
        ("Dinner is at 19:00.", "list"),
    ],
)
def test_facts_are_validated(facts: Any, problem: str) -> None:
    with pytest.raises(ScenarioError) as caught:
        parse(_judged(facts=facts))
    (found,) = caught.value.problems
    assert problem in str(found) and "facts" in str(found)


def test_facts_are_trimmed() -> None:
    scenario = parse(_judged(facts=["  Dinner is at 19:00. "]))
    judge = scenario.goals[0].checks[0].judge
    assert judge is not None and judge.facts == ["Dinner is at 19:00."]


def test_unused_facts_leave_the_dump_and_so_the_content_hash_as_before() -> None:
    plain, told = parse(_judged()), parse(_judged(facts=FACTS))
    assert "facts" not in plain.model_dump()["goals"][0]["checks"][0]["judge"]
    assert told.model_dump()["goals"][0]["checks"][0]["judge"]["facts"] == FACTS
    assert "judge" not in plain.model_dump()["events"][0]
    assert plain.content_hash() != told.content_hash()
