"""Why a matcher refused a value, in words an author can act on.

A failing check used to say only which matcher failed on how many texts ("fallback any of (affirms
['move*'] | ...) fails on 1 text(s)"); the author then had to read the matcher code to learn that the
clause holding "move" was negated by a "not" three words earlier. :func:`explain` says which part of the
matcher failed on which clause and why: ``affirms 'move*': found 'move' in clause "not Fri ... could we
move it" but it is negated by 'not'``.

Explanations are computed only for checks that fail (they read the text again, clause by clause), never
while checks run: a verdict's cost does not change when everything holds. Why a text fails a text
operator is the operator's own (its record's ``explain``, in :mod:`pare.scenarios.text_reasons` for the
built-in ones); an operator without one is explained by what it was given.
"""

from __future__ import annotations

from collections.abc import Mapping
from datetime import datetime
from typing import Any

from pare.scenarios.excerpts import CLAUSE_WIDTH, excerpt, quote
from pare.scenarios.matchers import OPERATORS, Matcher
from pare.scenarios.operators import item_texts

_MOST_ITEMS = 3
"""How many items of a list value are explained one by one."""


def explain(matcher: Matcher, value: Any, start: datetime) -> str:
    """Why ``matcher`` does not accept ``value`` (relative times resolved against ``start``); empty if it
    does. Each failing part is named with what it found, e.g. ``affirms 'move*': found 'move' in clause
    "not Fri ..." but it is negated by 'not'``.
    """
    if matcher.test(value, start):
        return ""
    if matcher.fields:
        return _explain_fields(matcher, value, start)
    reasons = []
    for name, expected in matcher.operators:
        single = Matcher(operators=((name, expected),))
        if not single.test(value, start):
            reasons.append(_explain_operator(single, name, expected, value, start))
    return "; ".join(reasons)


def _explain_fields(matcher: Matcher, value: Any, start: datetime) -> str:
    if isinstance(value, list):
        if not value:
            return "the list is empty"
        shown = [
            f"item {index}: {_explain_fields(matcher, item, start)}"
            for index, item in enumerate(value[:_MOST_ITEMS])
        ]
        more = f"; and {len(value) - _MOST_ITEMS} more" if len(value) > _MOST_ITEMS else ""
        return f"none of its {len(value)} items matches ({'; '.join(shown)}{more})"
    if not isinstance(value, Mapping):
        return f"not a record (got {_shown(value)})"
    reasons = []
    for key, field_matcher in matcher.fields:
        why = explain(field_matcher, value.get(key), start)
        if why:
            reasons.append(f"{key}: {why}")
    return "; ".join(reasons)


def _explain_operator(single: Matcher, name: str, expected: Any, value: Any, start: datetime) -> str:
    described = single.describe()
    if name == "not":
        return f"not ({expected.describe()}): it holds"
    if name == "any_of":
        return "any of: none holds (" + " | ".join(explain(option, value, start) for option in expected) + ")"
    if name == "present":
        return "the value is missing" if expected else f"the value is given ({_shown(value)})"
    if value is None:
        return f"{described}: the value is missing"
    operator = OPERATORS[name]
    if operator.explain is None:  # an operator that does not read text: what it was given says why
        return f"{described}: got {_shown(value)}"
    label = described if operator.label is None else operator.label(expected, start)
    texts = item_texts(value, name)
    reasons = [operator.explain(text, expected, start) for text in texts[:_MOST_ITEMS]]
    if len(texts) == 1:
        return f"{label}: {reasons[0]}"
    pairs = zip(texts, reasons, strict=False)
    shown = "; ".join(f"{quote(text, CLAUSE_WIDTH)}: {why}" for text, why in pairs)
    more = f"; and {len(texts) - _MOST_ITEMS} more" if len(texts) > _MOST_ITEMS else ""
    return f"{label}: in none of its {len(texts)} items ({shown}{more})"


def _shown(value: Any, width: int = 60) -> str:
    text = value if isinstance(value, str) else repr(value)
    return quote(text, width) if isinstance(value, str) else excerpt(text, (), width)
