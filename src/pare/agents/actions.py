"""The text action format of model-backed actors, as in the paper's prompts.

A model answers with its reasoning and exactly one tool call::

    Thought: I need the weather in Paris first.

    Action:
    {
      "action": "get_weather",
      "action_input": {"city": "Paris"}
    }<end_action>

:func:`parse_action` reads such an answer into a :class:`ParsedAction`, :func:`format_action` writes one
(for scripted models and the prompts' examples) and :func:`to_action` makes the episode loop's
:class:`~pare.agents.policy.Action` of it. A failure raises :class:`~pare.errors.ActionFormatError`, whose
message is written for the model: what was wrong, and how to answer instead.

The rule: what surrounds the JSON is read leniently, the JSON itself is never repaired.

Tolerated:

* whitespace around the answer; ``Action:`` in any case, also decorated (``**Action:**``) or on the
  thought's line when the JSON follows it directly;
* no ``Thought:`` label: the thought is then whatever precedes ``Action:`` (empty if nothing does);
* the JSON inside a Markdown fence, and text after the JSON (a closing fence, a stray ``}``, a remark);
* no ``<end_action>`` when the JSON object is complete; anything after ``<end_action>`` except another
  ``Action:``;
* an ``Observation:`` the model wrote itself: it and everything after it are ignored (an error says so if
  that leaves no action);
* raw line breaks and tabs inside JSON strings (kept as written);
* a thinking model's think blocks (``<think> ... </think>``, also a leading one whose ``<think>`` was in
  the prompt): taken out before the answer is read, whatever they hold (an ``Action:`` drafted while
  thinking is not one), and kept as :attr:`ParsedAction.reasoning`;
* ``action_input`` absent (no arguments), or a JSON string that holds an object (decoded).

Errors, each with its own message and :attr:`~pare.errors.ActionFormatError.kind`:

* an empty answer; no ``Action:`` (also: nothing but reasoning); no JSON object after it; a JSON array;
* JSON that does not parse, with dedicated messages for single quotes, trailing commas, Python's
  ``True``/``False``/``None``, comments, ``NaN``/``Infinity`` (and numbers too large for a double, such
  as ``1e999``, which would be infinite) and an object cut off before its end;
* more than one ``Action:`` or more than one JSON object: exactly one tool call per answer;
* ``action`` missing, not a string, or blank; keys other than ``action`` and ``action_input``;
  ``action_input`` present but not an object (``null`` and ``""`` included: a tool without input takes
  ``{}``, as the prompts say).
"""

from __future__ import annotations

import json
import math
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any, NoReturn

from pare.agents.models.reasoning import join_reasoning, split_reasoning
from pare.agents.models.text import may_hold_lone_surrogate, valid_json_value
from pare.agents.policy import Action
from pare.errors import ActionFormatError, did_you_mean

__all__ = ["END_ACTION", "FORMAT_HINT", "ParsedAction", "format_action", "parse_action", "to_action"]

END_ACTION = "<end_action>"
"""The tag that closes an action (also the stop sequence to give a model)."""

FORMAT_HINT = (
    'Answer with "Thought: <your reasoning>", then "Action:" and one JSON object '
    '{"action": "<tool name>", "action_input": {<arguments>}}, then <end_action>.'
)
"""How to answer; ends every :class:`~pare.errors.ActionFormatError` message."""

_KEYS = ("action", "action_input")

# An ``Action:`` label: at the start of a line (after Markdown decoration), or anywhere when a JSON
# value (possibly fenced) follows it directly. ``"action":`` inside JSON never matches: a quote
# separates the word from its colon.
_ACTION_RE = re.compile(
    r"^[ \t*_#>]*action[ \t*_]*:[*_]*"
    r"|\baction[ \t*_]*:[*_]*(?=\s*(?:```[\w-]*\s*)?[{\[])",
    re.IGNORECASE | re.MULTILINE,
)
_OBSERVATION_RE = re.compile(
    r"(?:^[ \t*_#>]*|</?end_action>[ \t]*)observation[ \t*_]*:",
    re.IGNORECASE | re.MULTILINE,
)
# What every match of the two labels above contains, within the one line it lies on: the word and its
# colon. Searched for first, so that the labels' patterns run only from the lines that may hold one
# (:func:`_labels`); run over a whole answer, their word-boundary and line-start tests at every
# position cost more than the rest of the parse.
_ACTION_WORD_RE = re.compile(r"action[ \t*_]*:", re.IGNORECASE)
_OBSERVATION_WORD_RE = re.compile(r"observation[ \t*_]*:", re.IGNORECASE)
_THOUGHT_RE = re.compile(r"^[ \t*_#>]*thought[ \t*_]*:[*_]*", re.IGNORECASE | re.MULTILINE)
_END_RE = re.compile(r"</?end_action>", re.IGNORECASE)
_JSON_START_RE = re.compile(r"[{\[]")
_OPEN_FENCE_AT_END_RE = re.compile(r"```[\w-]*\s*\Z")


@dataclass(frozen=True, slots=True)
class ParsedAction:
    """One answer in the action format, read."""

    thought: str
    """The reasoning before ``Action:`` (without its ``Thought:`` label); may be empty."""
    tool: str
    """The tool to call, exactly as the model named it under ``"action"``."""
    args: dict[str, Any] = field(default_factory=dict)
    """The arguments, from ``"action_input"``."""
    raw: str = ""
    """The whole answer as the model wrote it."""
    reasoning: str | None = None
    """A thinking model's reasoning: its think blocks and the reasoning given beside the answer."""


class _NonFiniteNumberError(ValueError):
    """A number no file of the run can hold: ``NaN``, ``Infinity`` or ``-Infinity``, or a number too large
    for a double (``1e999``), which Python would read as infinite; the message names it and says why.
    """


def _reject_constant(name: str) -> NoReturn:
    raise _NonFiniteNumberError(f"{name}, which is not a JSON number")


def _finite_float(text: str) -> float:
    value = float(text)
    if math.isinf(value):
        shown = text if len(text) <= 40 else f"{text[:20]}...{text[-10:]}"
        raise _NonFiniteNumberError(f"{shown}, a number too large to hold (it would be infinite)")
    return value


# strict=False: raw line breaks and tabs inside strings are kept as written.
_DECODER = json.JSONDecoder(strict=False, parse_constant=_reject_constant, parse_float=_finite_float)


def _fail(kind: str, problem: str) -> NoReturn:
    raise ActionFormatError(f"{problem} {FORMAT_HINT}", kind=kind)


def _json_kind(value: object) -> str:
    if value is None:
        return "null"
    if isinstance(value, bool):
        return f"the boolean {json.dumps(value)}"
    if isinstance(value, int | float):
        return f"the number {json.dumps(value)}"
    if isinstance(value, str):
        return "a string"
    if isinstance(value, list):
        return "an array"
    return "an object"


def _first_at_or_after(matches: Sequence[re.Match[str]], position: int) -> re.Match[str] | None:
    return next((m for m in matches if m.start() >= position), None)


def _labels(label: re.Pattern[str], word: re.Pattern[str], text: str) -> list[re.Match[str]]:
    """The matches of ``label`` in ``text``, exactly as ``label.finditer(text)`` gives them.

    Every match of ``label`` lies within one line and contains a match of ``word``, so none starts
    before the line of the next occurrence of ``word``: the search for ``label`` starts there.
    """
    found = []
    position = 0
    while (occurrence := word.search(text, position)) is not None:
        # the line's start, or where the last match ended if that is later (so no text is read twice)
        start = max(position, text.rfind("\n", position, occurrence.start()) + 1)
        match = label.search(text, start)
        if match is None:
            break
        found.append(match)
        position = match.end()  # never empty: a label holds its word
    return found


def parse_action(text: str, *, reasoning: str | None = None) -> ParsedAction:
    """Read a model's answer in the Thought/Action format.

    A thinking model's think blocks are taken out of ``text`` first
    (:func:`~pare.agents.models.reasoning.split_reasoning`) and never read as the answer, whatever they
    hold; ``reasoning`` is what the server returned beside the answer. Both are kept in the result.

    Raises:
        ActionFormatError: the answer is not exactly one tool call in the format; the message is
            written for the model and ends with :data:`FORMAT_HINT`.
    """
    raw = text
    text, inline_reasoning = split_reasoning(text)
    reasoning = join_reasoning(reasoning, inline_reasoning)
    if not text.strip():
        if reasoning is not None:
            _fail(
                "no_action",
                "Your answer held only your reasoning, with no Action: section after it, so no tool was "
                "called. Reasoning is never read as the answer: after thinking, write your answer.",
            )
        _fail("empty", "Your answer was empty, so no tool was called.")
    actions = _labels(_ACTION_RE, _ACTION_WORD_RE, text)
    observations = _labels(_OBSERVATION_RE, _OBSERVATION_WORD_RE, text)
    first_observation = observations[0].start() if observations else len(text)
    if not actions:
        _fail("no_action", "Your answer had no Action: section, so no tool was called.")
    marker = actions[0]
    if marker.start() >= first_observation:
        _fail(
            "observation",
            "Your answer wrote an Observation: before its Action:. Everything from Observation: on is "
            "ignored (the system writes the observation after running your action), so no tool was "
            "called. Write only Thought: and Action:.",
        )

    # The JSON: from the first '{' (or '[') after the label, before any Observation: or <end_action>.
    end_tag = _END_RE.search(text, marker.end())
    limit = min(first_observation, end_tag.start() if end_tag else len(text))
    opening = _JSON_START_RE.search(text, marker.end(), limit)
    if opening is None:
        if limit == first_observation < len(text) and _JSON_START_RE.search(text, first_observation):
            _fail(
                "observation",
                "Your Action: section had no JSON object before the Observation: you wrote; everything "
                "from Observation: on is ignored (the system writes observations), so no tool was called.",
            )
        where = " before <end_action>" if end_tag and end_tag.start() < first_observation else ""
        _fail(
            "no_json",
            f"Your Action: section had no JSON object{where}; write the tool call as a JSON object "
            "right after Action:.",
        )
    start = opening.start()
    several = len(actions) > 1  # most answers have one Action: (the one before the JSON): nothing to look at
    if several and any(marker.end() <= other.start() < start for other in actions[1:]):
        _multiple_actions()
    if text[start] == "[":
        _fail(
            "json_array",
            "Your Action: held a JSON array, but it takes one JSON object that calls exactly one tool. "
            "Make exactly one tool call per answer; you will see its result before your next answer.",
        )

    call, end = _decode_object(text, start, observations)

    # After the JSON: no second call, whether under another Action: or as another object.
    cut_match = _first_at_or_after(observations, end) if observations else None
    cut = cut_match.start() if cut_match else len(text)
    if several and any(end <= other.start() < cut for other in actions):
        _multiple_actions()
    tail_end = _END_RE.search(text, end, cut)
    brace = text.find("{", end, tail_end.start() if tail_end else cut)
    if brace != -1:
        try:
            second, _ = _DECODER.raw_decode(text, brace)
        except (ValueError, RecursionError):
            second = None
        if isinstance(second, dict):
            _fail(
                "multiple_json",
                "Your Action: section had more than one JSON object. Make exactly one tool call per answer; "
                "you will see its result before your next answer.",
            )

    tool, args = _read_call(call)
    return ParsedAction(
        thought=_thought(text[: marker.start()]), tool=tool, args=args, raw=raw, reasoning=reasoning
    )


def parse_tool_arguments(tool: str, arguments: str) -> dict[str, Any]:
    """Decode the JSON arguments of a native tool call, held to the same rules as the text format's.

    Raises:
        ActionFormatError: the arguments are not one JSON object (invalid JSON, ``NaN`` or
            ``Infinity``, which JSON lacks, or another kind of value); the message is for the model.
    """
    text = arguments.strip() or "{}"
    try:
        value, end = _DECODER.raw_decode(text)
    except _NonFiniteNumberError as exc:
        raise ActionFormatError(
            f"The arguments of {tool} contain {exc}; write a number or a string.",
            kind="non_finite_number",
        ) from None
    except (ValueError, RecursionError) as exc:
        raise ActionFormatError(
            f"The arguments of {tool} are not valid JSON ({exc}).", kind="invalid_json"
        ) from None
    if end != len(text):
        raise ActionFormatError(
            f"The arguments of {tool} hold more than one JSON value.", kind="invalid_json"
        )
    if not isinstance(value, dict):
        raise ActionFormatError(f"The arguments of {tool} must be a JSON object.", kind="invalid_json")
    return dict(valid_json_value(value))


def _multiple_actions() -> NoReturn:
    _fail(
        "multiple_actions",
        "Your answer had more than one Action: section. Make exactly one tool call per answer; you will see "
        "its result before your next answer.",
    )


def _decode_object(text: str, start: int, observations: Sequence[re.Match[str]]) -> tuple[Any, int]:
    """Decode the JSON object at ``text[start]`` (a ``{``), or fail with a message for the model."""
    try:
        value, end = _DECODER.raw_decode(text, start)
    except _NonFiniteNumberError as exc:
        _fail(
            "non_finite_number",
            f"Your Action JSON contains {exc}; write a number or a string.",
        )
    except json.JSONDecodeError as exc:
        _invalid_json(text, start, exc, observations)
    except RecursionError:
        _fail("invalid_json", "Your Action JSON is nested too deeply to read.")
    except ValueError as exc:  # e.g. an integer with too many digits
        _fail("invalid_json", f"Your Action JSON could not be read: {exc}.")
    # An escape such as "\\ud800" decodes to a lone surrogate, which no file of the run could hold; the
    # clean-up (which rebuilds every object and array) is left out for JSON that cannot hold one.
    return (valid_json_value(value) if may_hold_lone_surrogate(text, start, end) else value), end


def _invalid_json(
    text: str, start: int, exc: json.JSONDecodeError, observations: Sequence[re.Match[str]]
) -> NoReturn:
    pos = exc.pos
    line = text.count("\n", start, pos) + 1
    column = pos - (text.rfind("\n", start, pos) + 1 if line > 1 else start) + 1
    at = f"at line {line}, column {column} of the JSON"
    rest = text[pos:]
    before = text[start:pos].rstrip()
    unterminated = exc.msg.startswith("Unterminated string")
    if any(start < o.start() <= pos or (unterminated and o.start() > start) for o in observations):
        _fail(
            "observation",
            "Your Action JSON was cut off by the Observation: you wrote: everything from Observation: on is "
            "ignored (the system writes observations), and the JSON before it is not complete.",
        )
    if rest.startswith("'"):
        _fail(
            "single_quotes",
            f"Your Action JSON uses single quotes ({at}), which JSON does not allow: put keys and strings "
            'in double quotes, e.g. {"action": "tool_name"}.',
        )
    if before.endswith(",") and rest[:1] in ("}", "]"):
        _fail(
            "trailing_comma",
            f"Your Action JSON has a comma before a closing '{rest[0]}' ({at}), which JSON does not "
            "allow: remove that trailing comma.",
        )
    if rest.startswith(("True", "False", "None")):
        _fail(
            "python_literal",
            f"Your Action JSON uses Python's True/False/None ({at}); JSON writes them true, false and null.",
        )
    if rest.startswith(("//", "/*", "#")):
        _fail("comment", f"Your Action JSON contains a comment ({at}), which JSON does not allow: remove it.")
    if unterminated or not rest.strip() or _END_RE.match(rest.lstrip()) or rest.lstrip().startswith("```"):
        _fail(
            "incomplete_json",
            "Your Action JSON object is not complete: it ends before its closing '}'. Close every string, "
            "[ and { you open.",
        )
    near = rest[:20].split("\n", 1)[0]
    _fail("invalid_json", f"Your Action JSON is not valid JSON: {exc.msg} {at}, near {near!r}.")


def _read_call(call: dict[str, Any]) -> tuple[str, dict[str, Any]]:
    """The tool name and arguments of a decoded Action object, or fail with a message for the model."""
    if "action" not in call:
        keys = ", ".join(json.dumps(k) for k in call) or "none"
        _fail(
            "missing_tool",
            f'Your Action JSON has no "action" key naming the tool to call (its keys: {keys}).',
        )
    tool = call["action"]
    if not isinstance(tool, str):
        _fail(
            "bad_tool",
            f'"action" must be the name of one tool, as a string, not {_json_kind(tool)}.',
        )
    if not tool.strip():
        _fail("bad_tool", '"action" is empty: give the name of the tool to call.')
    unknown = [key for key in call if key not in _KEYS]
    if unknown:
        names = ", ".join(json.dumps(k) for k in unknown)
        _fail(
            "unknown_key",
            f"Your Action JSON has unexpected key(s) {names}.{did_you_mean(unknown[0], _KEYS)} It takes "
            'only "action" (the tool name) and "action_input" (its arguments).',
        )
    if "action_input" not in call:
        return tool, {}
    args = call["action_input"]
    if isinstance(args, str):
        try:
            decoded = _DECODER.decode(args)
        except _NonFiniteNumberError as exc:
            _fail("non_finite_number", f'"action_input" holds {exc}; write a number or a string.')
        except (ValueError, RecursionError):
            decoded = None
        if not isinstance(decoded, dict):
            _fail(
                "bad_input",
                '"action_input" is a string that does not hold a JSON object. Give the arguments as an '
                'object, e.g. "action_input": {"param": "value"}, or {} if the tool takes none.',
            )
        args = valid_json_value(decoded)  # arguments decoded a second time get the same clean-up of text
    if not isinstance(args, dict):
        _fail(
            "bad_input",
            f'"action_input" must be a JSON object of arguments, not {_json_kind(args)}; '
            "pass {} if the tool takes none.",
        )
    return tool, args


def _thought(before: str) -> str:
    label = _THOUGHT_RE.search(before)
    if label is not None:
        before = before[label.end() :]
    if "```" in before:  # what the fence pattern needs: most thoughts have none
        before = _OPEN_FENCE_AT_END_RE.sub("", before)
    return before.strip()


def format_action(tool: str, args: Mapping[str, Any] | None = None, thought: str = "") -> str:
    """Write one tool call in the action format, as a model should.

    ``parse_action(format_action(tool, args, thought))`` gives back ``tool``, the arguments as JSON
    gives them back, and ``thought`` without surrounding whitespace.

    Raises:
        ValueError: ``tool`` is blank, an argument is ``NaN`` or infinite, or ``thought`` would not read
            back (it holds a line that reads as ``Action:`` or ``Observation:``).
        TypeError: an argument is not JSON-serializable.
    """
    if not tool.strip():
        raise ValueError("the tool name is blank")
    body = json.dumps(
        {"action": tool, "action_input": dict(args or {})}, indent=2, ensure_ascii=False, allow_nan=False
    )
    label = f"Thought: {thought.strip()}".rstrip()
    text = f"{label}\n\nAction:\n{body}{END_ACTION}"
    try:
        parsed = parse_action(text)
    except ActionFormatError as exc:
        raise ValueError(f"this thought would not read back: {exc}") from exc
    if parsed.thought != thought.strip() or parsed.tool != tool:
        raise ValueError(f"this thought would not read back as written: {thought!r}")
    return text


def to_action(parsed: ParsedAction) -> Action:
    """The episode loop's action for a parsed answer, keeping what the model wrote."""
    return Action(tool=parsed.tool, args=dict(parsed.args), raw=parsed.raw)
