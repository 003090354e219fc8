"""Numbers a model writes that no JSON file can hold (``1e999`` is infinite once read) are the model's
format error, like ``NaN``: the episode completes, its trajectory is standard JSON, and a replay from the
cache gives the same file.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import pytest

from pare.agents.actions import END_ACTION, parse_action, parse_tool_arguments
from pare.cli import main
from pare.errors import ActionFormatError
from pare.generate.uniqueness import JudgeAnswerError, read_verdict
from pare.results.run_folder import EPISODES
from pare.testing import ChatServer, Reply, conversation_role, proactive_play
from tests.hardening.conftest import strict_json
from tests.hardening.test_model_output import only_record, run_command, server, trajectory_text

__all__ = ["server"]

TOO_LARGE = ["1e999", "-1E+400", "123456789.0e400"]


@pytest.mark.parametrize("number", TOO_LARGE)
def test_a_number_too_large_for_a_double_is_a_format_error(number: str) -> None:
    answer = f'Action:\n{{"action": "system__wait", "action_input": {{"minutes": {number}}}}}{END_ACTION}'
    with pytest.raises(ActionFormatError, match="too large to hold") as refused:
        parse_action(answer)
    assert refused.value.kind == "non_finite_number" and number in str(refused.value)
    as_string = json.dumps(json.dumps({"minutes": 1}).replace("1", number))  # action_input as a string
    with pytest.raises(ActionFormatError, match="too large to hold"):
        parse_action(f'Action:\n{{"action": "system__wait", "action_input": {as_string}}}{END_ACTION}')
    with pytest.raises(ActionFormatError, match="too large to hold") as native:
        parse_tool_arguments("system__wait", f'{{"minutes": {number}}}')
    assert native.value.kind == "non_finite_number"


def test_large_numbers_a_double_holds_are_kept() -> None:
    parsed = parse_action(f'Action:\n{{"action": "t", "action_input": {{"x": 1e300, "y": 2.5}}}}{END_ACTION}')
    assert parsed.args == {"x": 1e300, "y": 2.5}


def test_the_uniqueness_judge_s_unreadable_numbers_are_its_format_error() -> None:
    too_many_digits = "1" + "0" * 5_000  # Python refuses to read an integer this long
    too_deep = "[" * 100_000 + "]" * 100_000
    for value in (too_many_digits, too_deep):
        with pytest.raises(JudgeAnswerError, match="cannot be read"):
            read_verdict(f'{{"duplicate": false, "n": {value}}}')


def _wait_with(number: str, native: bool) -> Any:
    play = proactive_play()

    def respond(request: dict[str, Any]) -> Reply:
        reply = play(request)
        if conversation_role(request["messages"]) != "observe":
            return reply
        body = json.loads(json.dumps(reply.body))
        if native and "tools" in request:
            call = {"name": "system__wait", "arguments": f'{{"minutes": {number}}}'}
            body["choices"][0]["message"] = {
                "role": "assistant",
                "content": None,
                "tool_calls": [{"id": "call_1", "type": "function", "function": call}],
            }
        else:
            call = f'{{"action": "system__wait", "action_input": {{"minutes": {number}}}}}'
            body["choices"][0]["message"]["content"] = f"Thought: wait.\n\nAction:\n{call}{END_ACTION}"
        return Reply(200, body)

    return respond


@pytest.mark.parametrize("native", [False, True], ids=["text", "native_tool_call"])
def test_an_overflowing_number_in_an_answer_leaves_a_complete_episode_that_replays(
    tmp_path: Path, example_scenario: Path, server: ChatServer, native: bool
) -> None:
    server.responder = _wait_with("1e999", native)
    output = tmp_path / "run"
    extra = ["--set", "models.assistant.native_tools=true"] if native else []
    assert main(run_command(output, example_scenario, server, *extra)) == 0
    record = only_record(output)
    assert record["status"] == "complete", record["failure"]
    first = trajectory_text(output, record)
    strict_json(first)
    assert "1e999, a number too large to hold" in first

    (output / EPISODES).unlink()
    assert main(run_command(output, example_scenario, server, *extra, "--cache", "replay")) == 0
    assert trajectory_text(output, only_record(output)) == first
