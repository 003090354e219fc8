"""The gate plays a scenario's runs in one event loop and keeps each episode's result."""

from __future__ import annotations

import pytest

from pare.bench.episode import EpisodeResult
from pare.bench.selftest import check_scenario
from tests.scenarios.helpers import REPLY, intervention, parse, sound


def test_the_gate_keeps_every_result_without_formatting_it(monkeypatch: pytest.MonkeyPatch) -> None:
    """asyncio formats what a run returns when it puts the Ctrl-C handler back (quietly: a failing
    repr is swallowed); the gate hands its episodes back another way, since formatting one costs more
    than playing it."""
    formatted: list[str] = []

    def counted(self: EpisodeResult) -> str:
        formatted.append(self.scenario_id)
        return "<episode>"

    monkeypatch.setattr(EpisodeResult, "__repr__", counted)
    verdict = check_scenario(parse(sound()))
    assert verdict.ok, verdict.breaches()
    assert set(verdict.details) == {run.run for run in verdict.runs}
    assert formatted == []


HOLDING = {"tool": "email__reply_to_email", "args": {"email_id": "e_ann", "content": "Got it, let me check."}}
"""A first reply that names no day: the world asks back ("Which day?")."""


def _holding_then_answer() -> list[dict[str, object]]:
    """A holding reply, then the answer once Ann has asked back (an answer before her question is due
    withdraws it)."""
    answer = {
        **intervention(REPLY),
        "when": {"event": "ann_confirms_otherwise"},
        "proposal": "Tell Ann: Thursday.",
    }
    return [intervention(HOLDING), answer]


def _asks_then_answers(**extra: object) -> dict[str, object]:
    """A correct variant whose first reply gets Ann's correction, then gives the answer."""
    return {
        "id": "asks_then_answers",
        "expect": "pass",
        "why": "A holding reply, then Thursday, still tells Ann.",
        "interventions": _holding_then_answer(),
        **extra,
    }


def test_a_correct_variant_the_world_corrected_is_a_breach() -> None:
    data = sound()
    data["variants"].append(_asks_then_answers())
    verdict = check_scenario(parse(data))
    run = verdict.run("variant:asks_then_answers")
    assert run.success and not run.ok
    [line] = verdict.breaches()
    assert line.startswith("tiny_reply [variant:asks_then_answers]: variant 'asks_then_answers' passed")
    assert "otherwise branch of event 'ann_confirms' (\"Which day?\")" in line
    assert 'set off by #8 assistant email.reply_to_email "Got it, let me check."' in line
    assert [(event.event, event.branch) for event in run.events] == [
        ("ann_asks", "timed"),
        ("ann_confirms", "otherwise"),
        ("ann_confirms", "reply"),
    ]


def test_a_variant_may_say_why_the_correction_is_part_of_its_solution() -> None:
    data = sound()
    data["variants"].append(
        _asks_then_answers(otherwise_ok={"ann_confirms": "Ann asks; the answer follows."})
    )
    verdict = check_scenario(parse(data))
    assert verdict.ok, verdict.breaches()
    assert not verdict.warnings


def test_an_excuse_the_variant_never_needed_is_warned_about() -> None:
    data = sound()
    data["variants"][0]["otherwise_ok"] = {"ann_confirms": "A fresh email is never corrected."}
    verdict = check_scenario(parse(data))
    assert verdict.ok, verdict.breaches()
    assert verdict.warnings == (
        "variant:fresh_email declares otherwise_ok for event 'ann_confirms', but the world never answered "
        "it with that event's otherwise branch: drop the entry",
    )


def test_the_oracle_must_never_get_a_correction() -> None:
    data = sound()
    data["oracle"]["interventions"] = _holding_then_answer()
    verdict = check_scenario(parse(data), runs=("oracle",), variants=False)
    oracle = verdict.run("oracle")
    assert oracle.success and not oracle.ok
    assert "world answered the oracle with the otherwise branch of event 'ann_confirms'" in oracle.problems[0]


def test_a_wrong_variant_may_get_the_correction() -> None:
    verdict = check_scenario(parse(sound()))
    declines = verdict.run("variant:declines")
    assert declines.ok and ("ann_confirms", "otherwise") in [(e.event, e.branch) for e in declines.events]


@pytest.mark.parametrize("expect", ["pass", "fail"])
def test_a_scripted_call_that_fails_is_a_breach_whatever_the_variant_expects(expect: str) -> None:
    # a wrong variant that "fails" only because its own call broke proves nothing about the checks
    delete = {"tool": "email__delete_email", "args": {"email_id": "e_ann"}}  # the third finds nothing
    data = sound()
    data["variants"].append(
        {"id": "broken", "expect": expect, "why": "w", "interventions": [intervention(REPLY, *[delete] * 3)]}
    )
    verdict = check_scenario(parse(data), runs=("oracle",))
    run = verdict.run("variant:broken")
    assert not run.ok and not verdict.ok
    assert any("email.delete_email failed" in problem for problem in run.problems), run.problems
