"""Text a model returns, made safe to store: every string PARE writes must encode as UTF-8.

A model can produce lone UTF-16 surrogates (directly, or through a JSON escape of one in its action),
which Python strings hold but UTF-8 cannot encode: left in, they break hashing, the cache and every JSON
file of the run. They are replaced by U+FFFD, the replacement character, where the text enters PARE,
so whatever the model wrote is still judged as its behaviour.
"""

from __future__ import annotations

import re
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from pare.agents.models.types import Completion

_LONE_SURROGATE = re.compile("[\ud800-\udfff]")
REPLACEMENT = "\ufffd"


def valid_text(text: str) -> str:
    """Return ``text`` with each lone surrogate replaced by U+FFFD (the same object when it has none)."""
    return _LONE_SURROGATE.sub(REPLACEMENT, text) if _LONE_SURROGATE.search(text) else text


def may_hold_lone_surrogate(json_text: str, start: int, end: int) -> bool:
    """Whether the JSON in ``json_text[start:end]`` may decode to a lone surrogate: only a surrogate
    written as is, or a backslash-u escape (of one, or of a pair), can put one in a decoded value.
    """
    return (
        json_text.find("\\u", start, end) != -1 or _LONE_SURROGATE.search(json_text, start, end) is not None
    )


def valid_json_value(value: Any) -> Any:
    """Return a decoded JSON value with :func:`valid_text` applied to every string in it, keys included."""
    if isinstance(value, str):
        return valid_text(value)
    if isinstance(value, dict):
        return {valid_text(key): valid_json_value(item) for key, item in value.items()}
    if isinstance(value, list):
        return [valid_json_value(item) for item in value]
    return value


def cap_answer(completion: Completion, limit: int) -> Completion:
    """``completion`` within ``limit`` characters of answer (text plus tool-call arguments): a longer one
    has its text cut to ``limit``, its tool calls dropped and its length kept in ``cut_from``.
    """
    length = len(completion.text) + sum(len(call.arguments) for call in completion.tool_calls)
    if length <= limit or completion.cut_from is not None:
        return completion
    return completion.model_copy(
        update={"text": completion.text[:limit], "tool_calls": (), "cut_from": length}
    )
