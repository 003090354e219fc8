"""Reading a provider's refusal of one request parameter, so the request can go again without it.

Providers refuse a parameter by name with HTTP 400: OpenAI's body names it in ``param`` with the code
``unsupported_parameter`` or ``unsupported_value`` ("Unsupported parameter: 'max_tokens' is not supported
with this model. Use 'max_completion_tokens' instead."); other servers only say so in the message;
litellm refuses before sending ("gpt-5-mini doesn't support temperature=0.0", "anthropic does not support
parameters: ['seed']"). Only a parameter the request carried counts: a refusal naming anything else is
left to the usual error.
"""

from __future__ import annotations

import re
from collections.abc import Mapping
from typing import Any

from pare.agents.models.backends import classify_error
from pare.agents.models.capabilities import RENAMED_FOR_REASONING, Adjustment

_NAMED = (
    re.compile(r"unsupported (?:parameter|value)s?:?\s*'([\w.]+)'", re.IGNORECASE),
    re.compile(r"unrecognized request arguments? supplied:?\s*'?([\w.]+)", re.IGNORECASE),
    re.compile(r"(?:doesn't|does not|do not) support (?:the )?'?([\w.]+)'?\s*=", re.IGNORECASE),
    re.compile(r"'?([\w.]+)'? (?:is|are) not supported (?:with|by|for) this model", re.IGNORECASE),
    re.compile(r"unknown (?:parameter|field|argument):?\s*'?([\w.]+)", re.IGNORECASE),
    re.compile(r"([\w.]+)'?: extra inputs are not permitted", re.IGNORECASE),  # Anthropic
    re.compile(r"'loc': \('body', '([\w.]+)'\)[^}]*extra inputs are not permitted", re.IGNORECASE),  # vLLM
)
_LISTED = re.compile(r"does not support parameters:?\s*\[([^\]]*)\]", re.IGNORECASE)
_EITHER = re.compile(r"`?([\w.]+)`? and `?([\w.]+)`? cannot both be specified", re.IGNORECASE)
"""Anthropic's newer models take a temperature or a top_p, not both: the second named is left out."""
_INSTEAD = re.compile(r"use '([\w.]+)' instead", re.IGNORECASE)


def refused_parameter(error: BaseException | None, sent: Mapping[str, Any]) -> Adjustment | None:
    """The adjustment that answers ``error``, a refusal of one of the ``sent`` parameters; ``None`` when
    ``error`` refuses no parameter the request carried.
    """
    if error is None:
        return None
    status = getattr(error, "status_code", None)
    if status not in (400, 422):
        return None
    inner = _error_body(error)
    message = _message(error, inner)
    name = _refused_name(inner, message, sent)
    if name is None:
        return None
    code = inner.get("code") if isinstance(inner.get("code"), str) else None
    failure = classify_error(error)
    said = (failure.detail if failure is not None else message).strip().replace("\n", " ")
    if len(said) > 200:
        said = said[:197] + "..."
    why = f"the provider refused it (HTTP {status}{f', {code}' if code else ''}: {said})"
    instead = _INSTEAD.search(message)
    new_name = instead.group(1) if instead else RENAMED_FOR_REASONING.get(name)
    if new_name is not None and new_name != name and new_name not in sent:
        return Adjustment(name, "renamed", why, new_name, learned=True)
    return Adjustment(name, "dropped", why, learned=True)


def _error_body(error: BaseException) -> dict[str, Any]:
    body = getattr(error, "body", None)
    if isinstance(body, dict):
        inner = body.get("error", body)
        if isinstance(inner, dict):
            return inner
    return {}


def _message(error: BaseException, inner: Mapping[str, Any]) -> str:
    if isinstance(inner.get("message"), str):
        return str(inner["message"])
    message = getattr(error, "message", None)
    return message if isinstance(message, str) and message else str(error)


def _refused_name(inner: Mapping[str, Any], message: str, sent: Mapping[str, Any]) -> str | None:
    param = inner.get("param")
    if isinstance(param, str) and param in sent:
        return param
    for pattern in _NAMED:
        for match in pattern.finditer(message):
            name = str(match.group(1))
            if name in sent:
                return name
    either = _EITHER.search(message)
    if either is not None and either.group(1) in sent and either.group(2) in sent:
        return str(either.group(2))
    listed = _LISTED.search(message)
    if listed is not None:
        for listed_name in re.findall(r"[\w.]+", listed.group(1)):
            if listed_name in sent:
                return str(listed_name)
    return None
