"""Worlds read meaning like checks do: a reactive event with a ``judge`` asks the run's judge model whether
the triggering text says what it waits for, and its ``if_args`` rule decides without one."""

from __future__ import annotations

import asyncio
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import pytest

from pare.agents.judge import ModelJudge
from pare.agents.scripted import ScriptedModel
from pare.bench import run_episode
from pare.bench.episode import EpisodeResult, arun_episode
from pare.bench.selftest import check_scenario
from pare.cli import main
from pare.scenarios import OracleAssistant, OracleUser, ScenarioError
from pare.scenarios.checks import JudgeVerdict
from pare.testing import ChatServer, Reply, completion
from tests.scenarios.helpers import fair, intervention, parse, sound, to_yaml

CRITERION = "accepts Thursday"
FACTS = ["Ann asked whether Thursday works."]


def _judged(**extra: Any) -> dict[str, Any]:
    data = fair()
    event = data["events"][-1]
    assert event["id"] == "ann_confirms"
    event["judge"] = {"criterion": CRITERION, "facts": FACTS}
    event["if_args"].update(extra)
    return data


def _gated(**extra: Any) -> dict[str, Any]:
    """:func:`_judged` with what the gate also demands: what Ann is told read by a judge check."""
    data = _judged(**extra)
    data["goals"][0]["checks"].append(sound()["goals"][0]["checks"][-1])
    return data


def _fired(data: dict[str, Any], judge: Any = None) -> list[str]:
    scenario = parse(data)
    result = run_episode(scenario, OracleUser(scenario), OracleAssistant(scenario), judge=judge)
    return [
        entry.event_id for entry in result.env.log if entry.actor == "env" and entry.ok and entry.event_id
    ]


class Reader:
    """A judge that accepts a text with the word ``accepting`` and no 'not', and remembers what it was
    asked."""

    def __init__(self, accepting: str = "thursday") -> None:
        self.accepting = accepting
        self.asked: list[tuple[str, str, list[str]]] = []

    async def __call__(self, criterion: str, text: str, facts: Sequence[str] = ()) -> JudgeVerdict:
        self.asked.append((criterion, text, list(facts)))
        said = text.lower()
        if self.accepting in said and " not " not in said:
            return JudgeVerdict(True, "It accepts Thursday.")
        return JudgeVerdict(False, "It does not accept Thursday.")


def test_without_a_judge_the_rule_decides() -> None:
    assert _fired(_judged()) == ["ann_asks", "ann_confirms"]


def test_the_judge_reads_the_triggering_text_with_the_events_criterion_and_facts() -> None:
    reader = Reader()
    assert _fired(_judged(), reader) == ["ann_asks", "ann_confirms"]
    assert reader.asked == [(CRITERION, "Yes, Thursday works for me!", FACTS)]


def test_a_text_the_judge_refuses_gets_the_correction_though_the_rule_would_accept_it() -> None:
    model = ScriptedModel(["NO\nIt does not accept Thursday."])
    fired = _fired(_judged(), ModelJudge(model))  # a model judge, called from inside the episode's event loop
    assert fired == ["ann_asks", "ann_confirms_otherwise"]
    assert "Criterion: accepts Thursday" in (model.requests[0][1].content or "")


def test_the_rest_of_if_args_still_holds_beside_the_judges_reading() -> None:
    assert _fired(_judged(email_id="e1"), Reader()) == ["ann_asks", "ann_confirms_otherwise"]


def test_an_event_without_a_judge_is_read_by_its_rule_even_when_the_run_has_one() -> None:
    reader = Reader()
    assert _fired(fair(), reader) == ["ann_asks", "ann_confirms"] and reader.asked == []


def test_the_judge_must_read_a_field_the_rule_tests() -> None:
    data = _judged()
    data["events"][-1]["judge"]["field"] = "subject"
    with pytest.raises(ScenarioError, match="'judge' reads 'subject', which 'if_args' does not test"):
        parse(data)


def test_the_gate_names_texts_the_rule_and_the_judge_read_apart() -> None:
    data = _gated()
    hedge = {
        "tool": "email__reply_to_email",
        "args": {"email_id": "e_ann", "content": "Thursday? I will check."},
    }
    data["variants"].append(
        {
            "id": "hedges",
            "expect": "pass",
            "why": "The goal's rule reads a day.",
            "interventions": [intervention(hedge)],
        }
    )
    reader = Reader(accepting="works")
    verdict = check_scenario(parse(data), judge=reader)
    assert verdict.ok, verdict.breaches()
    (line,) = verdict.warnings  # the declined reply: both say no
    assert line.startswith("[variant:hedges] event 'ann_confirms' on #")
    assert line.endswith(
        "'Thursday? I will check.': the rule says yes, the judge no (It does not accept Thursday.)"
    )
    texts = [text for _, text, _ in reader.asked]
    assert len(texts) == len(set(texts))  # each text judged once, though several runs wrote it
    assert not check_scenario(parse(_judged())).warnings  # no judge, nothing to compare


def test_pare_scenarios_check_asks_a_judge_model_on_a_local_server(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setenv("COLUMNS", "200")
    (tmp_path / "tiny_reply.yaml").write_text(to_yaml(_gated()))
    asked: list[str] = []

    def refuses(body: dict[str, Any]) -> Reply:
        asked.append(body["messages"][-1]["content"])
        return completion("NO\nIt is not clear enough.")

    with ChatServer(refuses) as server:
        flags = ["--judge-model", "judge", "--judge-endpoint", server.base_url, "--judge-key-env", "none"]
        assert main(["scenarios", "check", "-j", "1", str(tmp_path), *flags]) == 0
    out = capsys.readouterr().out
    assert "all 1 scenarios pass the gate" in out
    assert "the rule says yes, the judge no (It is not clear enough.)" in out
    assert asked and all("Criterion: accepts Thursday" in question for question in asked)
    assert main(["scenarios", "check", str(tmp_path), "--judge-model", "j", "--judge-provider", "nope"]) == 2
    assert "--judge-* flags: backend" in capsys.readouterr().err


class Meeting:
    """A judge whose first reading in each episode waits until the other episode's has begun: it can
    answer only if neither episode's judge holds up the event loop they share."""

    def __init__(self, episodes: int) -> None:
        self.episodes = episodes
        self.asked = 0
        self.everyone_asked = asyncio.Event()

    async def __call__(self, criterion: str, text: str, facts: Sequence[str] = ()) -> JudgeVerdict:
        self.asked += 1
        if self.asked >= self.episodes:
            self.everyone_asked.set()
        await asyncio.wait_for(self.everyone_asked.wait(), timeout=10)
        return JudgeVerdict(True, "It accepts Thursday.")


def test_the_judge_is_awaited_in_the_episodes_loop_while_other_episodes_play() -> None:
    scenario = parse(_judged())
    judge = Meeting(episodes=2)

    async def side_by_side() -> list[EpisodeResult]:
        return await asyncio.gather(
            *(
                arun_episode(scenario, OracleUser(scenario), OracleAssistant(scenario), judge=judge)
                for _ in "ab"
            )
        )

    for result in asyncio.run(side_by_side()):
        fired = [entry.event_id for entry in result.env.log if entry.actor == "env" and entry.event_id]
        assert fired == ["ann_asks", "ann_confirms"]
    assert judge.asked == 2
