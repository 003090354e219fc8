"""Text written as a YAML folded or literal block reaches the apps as written, without YAML's final line
break (a message written with ``content: >`` was sent with a trailing newline)."""

from __future__ import annotations

from pare.bench import run_episode
from pare.scenarios import OracleAssistant, OracleUser, parse_scenario
from pare.yaml_source import parse_yaml
from tests.scenarios.helpers import base, to_yaml


def _with_blocks() -> str:
    text = to_yaml(base())
    text = text.replace(
        "    content: Does Thursday work?\n",
        "    content: >\n      Does Thursday\n      work?\n",
    )
    text = text.replace(
        "        content: Thursday works!\n",
        "        content: |\n          Thursday works!\n          See you then.\n",
    )
    return text.replace(
        "    proposal: Reply to Ann that Thursday works.\n",
        "    proposal: &ask >\n      Reply to Ann that\n      Thursday works.\n    answer: *ask\n",
    )


def test_folded_and_literal_blocks_reach_the_apps_without_a_trailing_newline() -> None:
    scenario = parse_scenario(_with_blocks(), source="blocks.yaml")
    assert scenario.events[0].args["content"] == "Does Thursday work?"
    intervention = scenario.oracle.interventions[0]
    assert intervention.proposal == intervention.answer == "Reply to Ann that Thursday works."
    result = run_episode(scenario, OracleUser(scenario), OracleAssistant(scenario))
    assert result.success
    emails = result.env.snapshot()["email"]["emails"]
    assert emails["e_ann"]["content"] == "Does Thursday work?"
    (sent,) = [email for email in emails.values() if email["folder"] == "SENT"]
    assert sent["content"] == "Thursday works!\nSee you then."


def test_only_the_one_line_break_yaml_adds_is_dropped() -> None:
    text = (
        "a: |\n  one\n\n  two\nb: |+\n  kept\n\nc: >-\n  stripped\nd: |2\n    indented\ne: 'quoted\n\n  '\n"
    )
    data = parse_yaml(text, clip_block_scalars=True).data
    assert data == {"a": "one\n\ntwo", "b": "kept\n\n", "c": "stripped", "d": "  indented", "e": "quoted\n"}
    assert parse_yaml(text).data["a"] == "one\n\ntwo\n"  # other YAML files are read as YAML says
