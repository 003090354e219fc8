"""The Thought/Action text format: what is read, what is refused, and with which message for the model."""

from __future__ import annotations

import json
import math
import re
import time
from pathlib import Path
from typing import Any

import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

from pare.agents import actions
from pare.agents.actions import END_ACTION, FORMAT_HINT, ParsedAction, format_action, parse_action, to_action
from pare.agents.policy import Action
from pare.errors import ActionFormatError, ToolError

CANONICAL = """Thought: I need the weather in Paris before answering.

Action:
{
  "action": "get_weather",
  "action_input": {
    "city": "Paris"
  }
}<end_action>"""

# (id, answer, tool, args, thought)
TOLERATED: list[tuple[str, str, str, dict[str, Any], str]] = [
    (
        "canonical",
        CANONICAL,
        "get_weather",
        {"city": "Paris"},
        "I need the weather in Paris before answering.",
    ),
    (
        "surrounding whitespace",
        f"\n\n  {CANONICAL}  \n\n",
        "get_weather",
        {"city": "Paris"},
        "I need the weather",
    ),
    (
        "text after end_action",
        CANONICAL + "\nI hope this helps! {not json",
        "get_weather",
        {"city": "Paris"},
        "I",
    ),
    ("no end_action", CANONICAL.removesuffix(END_ACTION), "get_weather", {"city": "Paris"}, "I need"),
    (
        "no end_action, trailing remark",
        'Thought: t\nAction:\n{"action": "a", "action_input": {}}\nThat is my call.',
        "a",
        {},
        "t",
    ),
    (
        "json fence",
        'Thought: t\n\nAction:\n```json\n{"action": "a", "action_input": {"x": 1}}\n```\n<end_action>',
        "a",
        {"x": 1},
        "t",
    ),
    (
        "fence opened before Action:",
        'Thought: t\n```\nAction:\n{"action": "a", "action_input": {}}\n```',
        "a",
        {},
        "t",
    ),
    ("lower-case action", 'Thought: t\naction:\n{"action": "a", "action_input": {}}', "a", {}, "t"),
    (
        "upper-case labels",
        'THOUGHT: t\nACTION: {"action": "a", "action_input": {}}<END_ACTION>',
        "a",
        {},
        "t",
    ),
    ("markdown labels", '**Thought:** t\n**Action:**\n{"action": "a"}<end_action>', "a", {}, "t"),
    (
        "action on the thought's line",
        'Thought: I will wait. Action: {"action": "wait"}',
        "wait",
        {},
        "I will wait.",
    ),
    ("no thought at all", 'Action:\n{"action": "wait", "action_input": {}}<end_action>', "wait", {}, ""),
    ("unlabelled reasoning", 'I should wait.\nAction:\n{"action": "wait"}', "wait", {}, "I should wait."),
    ("action_input absent", 'Thought: t\nAction:\n{"action": "wait"}<end_action>', "wait", {}, "t"),
    (
        "action_input as a string holding an object",
        'Thought: t\nAction:\n{"action": "a", "action_input": "{\\"city\\": \\"Paris\\"}"}<end_action>',
        "a",
        {"city": "Paris"},
        "t",
    ),
    (
        "braces and tags inside strings",
        'Action:\n{"action": "a", "action_input": {"body": "x}{ \\"Action: {}\\" <end_action> ]"}}'
        "<end_action>",
        "a",
        {"body": 'x}{ "Action: {}" <end_action> ]'},
        "",
    ),
    (
        "raw line break inside a string",
        'Action:\n{"action": "a", "action_input": {"body": "Hi Bob,\nAction: see you\nObservation: x"}}',
        "a",
        {"body": "Hi Bob,\nAction: see you\nObservation: x"},
        "",
    ),
    (
        "an Observation written after the action",
        CANONICAL + '\n\nObservation: sunny\n\nThought: now report\nAction:\n{"action": "b"}<end_action>',
        "get_weather",
        {"city": "Paris"},
        "I need",
    ),
    (
        "an Observation right after end_action",
        'Action:\n{"action": "a"}<end_action>Observation: ok\nAction:\n{"action": "b"}<end_action>',
        "a",
        {},
        "",
    ),
    (
        "stray closing brace",
        'Action:\n{"action": "a", "action_input": {"x": 1}}}<end_action>',
        "a",
        {"x": 1},
        "",
    ),
    (
        "nested values",
        'Action:\n{"action": "a", "action_input": {"l": [1, 2.5, null, true], "o": {"p": {}}}}',
        "a",
        {"l": [1, 2.5, None, True], "o": {"p": {}}},
        "",
    ),
    (
        "paper's example cycle",
        "Thought: I need to look up the current weather before answering, so I will call the weather tool "
        'with the city name.\n\nAction:\n{\n  "action": "get_weather",\n  "action_input": {\n    "city": '
        '"Paris"\n  }\n}<end_action>\n\nObservation: The current temperature in Paris is 20 degrees Celsius.',
        "get_weather",
        {"city": "Paris"},
        "I need to look up",
    ),
]


@pytest.mark.parametrize(
    ("text", "tool", "args", "thought"), [case[1:] for case in TOLERATED], ids=[case[0] for case in TOLERATED]
)
def test_tolerated_answers_are_read(text: str, tool: str, args: dict[str, Any], thought: str) -> None:
    parsed = parse_action(text)
    assert (parsed.tool, parsed.args) == (tool, args)
    assert parsed.thought.startswith(thought)
    assert parsed.thought == parsed.thought.strip()
    assert parsed.raw == text


# (id, answer, kind, fragments of the message)
MALFORMED: list[tuple[str, str, str, tuple[str, ...]]] = [
    ("empty", "", "empty", ("was empty",)),
    ("whitespace only", " \n\t ", "empty", ("was empty",)),
    ("no action", "Thought: I will just think about it.", "no_action", ("no Action: section",)),
    ("bare json", '{"action": "a", "action_input": {}}', "no_action", ("no Action: section",)),
    ("action label inside a word", 'Reaction: {"action": "a"}', "no_action", ("no Action: section",)),
    ("no json after action", "Thought: t\nAction: get_weather(city='Paris')", "no_json", ("no JSON object",)),
    (
        "json only after end_action",
        'Action: <end_action>\n{"action": "a"}',
        "no_json",
        ("before <end_action>",),
    ),
    (
        "json array",
        'Action:\n[{"action": "a"}, {"action": "b"}]',
        "json_array",
        ("JSON array", "exactly one tool"),
    ),
    (
        "two action sections",
        'Action:\n{"action": "a"}<end_action>\nThought: then\nAction:\n{"action": "b"}<end_action>',
        "multiple_actions",
        ("more than one Action:", "exactly one tool call per answer"),
    ),
    (
        "an empty action label then another",
        'Action: let me think\nAction:\n{"action": "a"}',
        "multiple_actions",
        ("more than one Action:",),
    ),
    (
        "two json objects",
        'Action:\n{"action": "a"}\n{"action": "b"}<end_action>',
        "multiple_json",
        ("more than one JSON object", "exactly one tool call per answer"),
    ),
    (
        "observation before the action",
        'Thought: t\nObservation: the user opened mail\nAction:\n{"action": "a"}<end_action>',
        "observation",
        ("Observation: before its Action:", "ignored"),
    ),
    (
        "observation between label and json",
        'Action:\nObservation: ok\n{"action": "a"}',
        "observation",
        ("before the Observation: you wrote",),
    ),
    (
        "observation cutting the json",
        'Action:\n{"action": "a",\nObservation: done',
        "observation",
        ("cut off by the Observation: you wrote",),
    ),
    (
        "single quotes",
        "Action:\n{'action': 'a', 'action_input': {}}",
        "single_quotes",
        ("single quotes", "line 1"),
    ),
    ("single-quoted value", "Action:\n{\"action\": 'a'}", "single_quotes", ("double quotes",)),
    (
        "trailing comma in object",
        'Action:\n{"action": "a", "action_input": {"x": 1,}}',
        "trailing_comma",
        ("comma before a closing '}'", "remove that trailing comma"),
    ),
    (
        "trailing comma in array",
        'Action:\n{"action": "a", "action_input": {"x": [1, 2,]}}',
        "trailing_comma",
        ("closing ']'",),
    ),
    (
        "python literals",
        'Action:\n{"action": "a", "action_input": {"flag": True}}',
        "python_literal",
        ("true, false and null",),
    ),
    ("comment", 'Action:\n{\n  "action": "a" // the tool\n}', "comment", ("comment", "line 2")),
    (
        "NaN",
        'Action:\n{"action": "a", "action_input": {"x": NaN}}',
        "non_finite_number",
        ("NaN", "not a JSON number"),
    ),
    (
        "Infinity",
        'Action:\n{"action": "a", "action_input": {"x": -Infinity}}',
        "non_finite_number",
        ("-Infinity",),
    ),
    ("cut off", 'Action:\n{"action": "a", "action_input": {"x": 1}', "incomplete_json", ("not complete",)),
    (
        "unterminated string",
        'Action:\n{"action": "a", "action_input": {"x": "ab',
        "incomplete_json",
        ("not complete",),
    ),
    (
        "closed by end_action too early",
        'Action:\n{"action": "a", "action_input": {}<end_action>',
        "incomplete_json",
        ("not complete",),
    ),
    (
        "closed by a fence too early",
        'Action:\n```json\n{"action": "a"\n```',
        "incomplete_json",
        ("not complete",),
    ),
    (
        "missing comma",
        'Action:\n{"action": "a" "action_input": {}}',
        "invalid_json",
        ("Expecting ',' delimiter",),
    ),
    ("too deep", 'Action:\n{"a": ' + "[" * 100_000, "invalid_json", ("nested too deeply",)),
    (
        "too many digits",
        'Action:\n{"action": "a", "x": ' + "9" * 5000 + "}",
        "invalid_json",
        ("could not be read",),
    ),
    (
        "no action key",
        'Action:\n{"tool": "a", "args": {}}',
        "missing_tool",
        ('no "action" key', '"tool", "args"'),
    ),
    ("action not a string", 'Action:\n{"action": ["a", "b"]}', "bad_tool", ("not an array",)),
    ("action a number", 'Action:\n{"action": 3}', "bad_tool", ("not the number 3",)),
    ("action null", 'Action:\n{"action": null}', "bad_tool", ("not null",)),
    ("action blank", 'Action:\n{"action": "  "}', "bad_tool", ('"action" is empty',)),
    (
        "misspelt action_input",
        'Action:\n{"action": "a", "action_inputs": {"x": 1}}',
        "unknown_key",
        ('"action_inputs"', "Did you mean 'action_input'"),
    ),
    ("extra key", 'Action:\n{"action": "a", "thought": "t"}', "unknown_key", ('"thought"', 'only "action"')),
    (
        "action_input null",
        'Action:\n{"action": "a", "action_input": null}',
        "bad_input",
        ("not null", "pass {}"),
    ),
    ("action_input list", 'Action:\n{"action": "a", "action_input": [1]}', "bad_input", ("not an array",)),
    (
        "action_input bool",
        'Action:\n{"action": "a", "action_input": false}',
        "bad_input",
        ("the boolean false",),
    ),
    (
        "action_input empty string",
        'Action:\n{"action": "a", "action_input": ""}',
        "bad_input",
        ("string that does not hold a JSON object",),
    ),
    (
        "action_input string holding a list",
        'Action:\n{"action": "a", "action_input": "[1, 2]"}',
        "bad_input",
        ("string that does not hold a JSON object",),
    ),
]


@pytest.mark.parametrize(
    ("text", "kind", "fragments"), [case[1:] for case in MALFORMED], ids=[case[0] for case in MALFORMED]
)
def test_malformed_answers_get_their_own_message(text: str, kind: str, fragments: tuple[str, ...]) -> None:
    with pytest.raises(ActionFormatError) as caught:
        parse_action(text)
    error = caught.value
    assert error.kind == kind, str(error)
    message = str(error)
    for fragment in fragments:
        assert fragment in message, message
    assert message.endswith(FORMAT_HINT)
    assert isinstance(error, ToolError)  # returned to the actor as its observation


def test_every_failure_kind_is_in_the_table_and_has_its_own_message() -> None:
    source = Path(__file__).parents[2].joinpath("src/pare/agents/actions.py").read_text()
    kinds_in_module = set(re.findall(r'_fail\(\s*"(\w+)"', source)) | {"multiple_actions"}
    assert {case[2] for case in MALFORMED} == kinds_in_module
    messages: dict[str, set[str]] = {}
    for _, text, kind, _ in MALFORMED:
        with pytest.raises(ActionFormatError) as caught:
            parse_action(text)
        messages.setdefault(kind, set()).add(str(caught.value))
    for kind, texts in messages.items():
        for other, other_texts in messages.items():
            assert other == kind or not texts & other_texts, (kind, other)


def test_to_action_keeps_what_the_model_wrote() -> None:
    parsed = parse_action(CANONICAL)
    assert to_action(parsed) == Action("get_weather", {"city": "Paris"}, CANONICAL)
    action = to_action(ParsedAction("", "wait", {}, "x"))
    assert (action.tool, action.args, action.raw) == ("wait", {}, "x")


def test_format_action_writes_the_papers_format() -> None:
    assert format_action(
        "get_weather", {"city": "Paris"}, "I need the weather in Paris before answering."
    ) == (CANONICAL)
    assert (
        format_action("wait")
        == 'Thought:\n\nAction:\n{\n  "action": "wait",\n  "action_input": {}\n}<end_action>'
    )


@pytest.mark.parametrize(
    ("tool", "args", "thought", "error"),
    [
        ("  ", {}, "", ValueError),
        ("a", {"x": math.nan}, "", ValueError),
        ("a", {}, "first\nAction: something else", ValueError),
        ("a", {}, "first\nObservation: x", ValueError),
        ("a", {"x": object()}, "", TypeError),
    ],
)
def test_format_action_refuses_what_would_not_read_back(
    tool: str, args: dict[str, Any], thought: str, error: type[Exception]
) -> None:
    with pytest.raises(error):
        format_action(tool, args, thought)


# --- properties ---------------------------------------------------------------------------------------

FRAGMENTS = [
    "Thought:",
    "Action:",
    "action:",
    "**Action:**",
    "Observation:",
    END_ACTION,
    "```json",
    "```",
    "{",
    "}",
    "[",
    "]",
    '"action"',
    '"action_input"',
    ":",
    ",",
    '"',
    "'",
    "\\",
    "\n",
    " ",
    "NaN",
    "True",
    "null",
    "1",
    "//",
    '"a"',
    "{}",
    '"{}"',
]

answers_made_of_fragments = st.lists(
    st.one_of(st.sampled_from(FRAGMENTS), st.text(max_size=4)), max_size=40
).map("".join)


LABEL_FRAGMENTS = [
    "action",
    "ACTION",
    "act\u0131on",  # a dotless i: the same word to a case-insensitive pattern
    "observation",
    "Observation",
    ":",
    " ",
    "\t",
    "\n",
    "*",
    "_",
    "#",
    ">",
    "<end_action>",
    "</end_action>",
    "{",
    "[",
    "```json",
    "x",
    '"',
]
texts_around_labels = st.lists(
    st.one_of(st.sampled_from(LABEL_FRAGMENTS), st.text(max_size=3)), max_size=30
).map("".join)


@settings(max_examples=1000, deadline=None)
@given(texts_around_labels)
@example("**Action: x\nthe action: {} and ACTION:\n{}")
@example("Thought: x\n> Observation: y <end_action> observation: z\n_observation_:")
def test_labels_are_found_as_a_scan_of_the_whole_answer_finds_them(text: str) -> None:
    for label, word in (
        (actions._ACTION_RE, actions._ACTION_WORD_RE),
        (actions._OBSERVATION_RE, actions._OBSERVATION_WORD_RE),
    ):
        found = [match.span() for match in actions._labels(label, word, text)]
        assert found == [match.span() for match in label.finditer(text)]


def read_or_refuse(text: str) -> None:
    try:
        parsed = parse_action(text)
    except ActionFormatError as error:
        assert str(error).endswith(FORMAT_HINT)
        assert error.kind
    else:
        assert isinstance(parsed.tool, str) and parsed.tool.strip()
        assert isinstance(parsed.args, dict)
        assert parsed.raw == text


@settings(max_examples=300, deadline=None)
@given(st.text())
def test_arbitrary_text_is_read_or_refused_with_a_format_error(text: str) -> None:
    read_or_refuse(text)


@settings(max_examples=500, deadline=None)
@given(answers_made_of_fragments)
def test_answers_made_of_format_pieces_are_read_or_refused_with_a_format_error(text: str) -> None:
    read_or_refuse(text)


@settings(max_examples=200, deadline=None)
@given(st.text(max_size=30), answers_made_of_fragments)
def test_noise_around_a_valid_answer_is_read_or_refused_with_a_format_error(before: str, after: str) -> None:
    read_or_refuse(before + CANONICAL + after)


json_values = st.recursive(
    st.none() | st.booleans() | st.integers() | st.floats(allow_nan=False, allow_infinity=False) | st.text(),
    lambda children: st.lists(children, max_size=4) | st.dictionaries(st.text(), children, max_size=4),
    max_leaves=12,
)
tool_names = st.text(min_size=1).filter(str.strip)
plain_thoughts = st.text(st.characters(blacklist_characters=":`", blacklist_categories=("Cs",)))


@settings(max_examples=300, deadline=None)
@given(tool_names, st.dictionaries(st.text(), json_values, max_size=5), plain_thoughts)
def test_format_action_round_trips(tool: str, args: dict[str, Any], thought: str) -> None:
    parsed = parse_action(format_action(tool, args, thought))
    assert (parsed.tool, parsed.args, parsed.thought) == (tool, json.loads(json.dumps(args)), thought.strip())


@settings(max_examples=300, deadline=None)
@given(st.sampled_from(["wait", "email__send"]), st.text())
def test_format_action_round_trips_any_thought_or_refuses_it(tool: str, thought: str) -> None:
    try:
        text = format_action(tool, {}, thought)
    except ValueError:
        return
    parsed = parse_action(text)
    assert (parsed.tool, parsed.thought) == (tool, thought.strip())


@pytest.mark.parametrize(
    "text",
    [
        " " * 200_000 + "x",
        "\n".join([" \t*" * 2_000 + "x"] * 50),
        "Thought:" + " " * 100_000 + "x\nAction: " + " " * 100_000 + "{",
        'Action: {"action": "a"}' + "{" * 100_000,
        "Action:\n" * 20_000,
        "a action: {" * 50_000,
    ],
    ids=[
        "long blank line",
        "many decorated lines",
        "long gaps",
        "many braces",
        "many labels",
        "labels on a line",
    ],
)
def test_pathological_answers_are_handled_in_linear_time(text: str) -> None:
    # Not a speed test (benchmarks/ measure speed): a pattern that backtracks on these inputs would take
    # hours, so a bound far above any machine's load tells a catastrophe from a slow machine.
    started = time.perf_counter()
    read_or_refuse(text)
    assert time.perf_counter() - started < 30.0


def test_arguments_given_as_a_json_string_get_no_lone_surrogate() -> None:
    """An escaped lone surrogate inside a string-encoded action_input cannot be written as UTF-8 later."""
    inner = json.dumps({"content": "hi \\ud800 there"}).replace("\\\\ud800", "\\ud800")
    call = json.dumps({"action": "messaging__send_message", "action_input": inner})
    text = f"Action:\n{call}\n<end_action>"
    parsed = parse_action(text)
    assert parsed.args == {"content": "hi \ufffd there"}
    parsed.args["content"].encode("utf-8")


@pytest.mark.parametrize(
    ("written", "read"),
    [
        ('"hi \\ud800 there"', "hi \ufffd there"),  # an escaped lone surrogate
        ('"hi \ud800 there"', "hi \ufffd there"),  # one written as is
        ('"\\ud83d\\ude00 and \\u00e9"', "\U0001f600 and \u00e9"),  # escapes of a pair and of a letter
        ('"plain"', "plain"),
    ],
)
def test_the_action_json_gets_no_lone_surrogate_in_values_or_keys(written: str, read: str) -> None:
    arguments = f'{{"body": {written}, {written}: [{written}]}}'
    text = f'Action:\n{{"action": "notes__create", "action_input": {arguments}}}'
    parsed = parse_action(text)
    assert parsed.args == {"body": read, read: [read]}
    json.dumps(parsed.args, ensure_ascii=False).encode("utf-8")
