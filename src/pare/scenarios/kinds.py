"""Whether a matcher can apply to a field: catching silent authoring mistakes before any run.

A matcher that can never hold is a silent error: ``contains`` on a number, ``min`` on a list, or an
operator misspelt (``contain_any``), which the matcher syntax reads as the name of a record field and
which then quietly matches nothing. Knowing each field's type (from the app's state models and the tools'
signatures) turns these into load errors with their place.
"""

from __future__ import annotations

import enum
import types
import typing
from collections.abc import Iterator, Mapping
from datetime import date, datetime
from decimal import Decimal
from typing import Any, Literal

from pydantic import BaseModel

from pare.errors import did_you_mean
from pare.scenarios.annotations import strip_optional
from pare.scenarios.matchers import OPERATORS, Reads

Kind = Literal["text", "number", "bool", "time", "list", "record", "any"]
"""What a field holds, as far as matchers are concerned."""

_SCALARS: tuple[Kind, ...] = ("text", "number", "bool", "time")
_APPLIES_TO: dict[Reads, frozenset[Kind]] = {
    "text": frozenset({"text", "list", "record", "any", "time"}),
    "number": frozenset({"number", "text", "any"}),
    "time": frozenset({"time", "text", "any"}),
    "list": frozenset({"list", "any"}),
}
"""The kinds of fields an operator applies to, by what it reads (``Operator.reads``); those that compare
values or run other matchers (equals, present, not) apply to anything."""
_NOUNS: dict[Kind, str] = {
    "text": "text",
    "number": "a number",
    "bool": "a true/false value",
    "time": "a time",
    "list": "a list",
    "record": "a record",
    "any": "anything",
}


def kind_of(annotation: Any) -> Kind:
    """The kind of values a field of type ``annotation`` holds."""
    annotation = strip_optional(annotation)
    origin = typing.get_origin(annotation)
    if origin is Literal:
        values = typing.get_args(annotation)
        return "text" if all(isinstance(v, str) for v in values) else "any"
    if origin in (list, tuple, set, frozenset):
        return "list"
    if origin is dict:
        return "record"
    if origin in (typing.Union, types.UnionType):
        kinds = {kind_of(option) for option in typing.get_args(annotation) if option is not type(None)}
        return kinds.pop() if len(kinds) == 1 else "any"
    if not isinstance(annotation, type):
        return "any"
    if issubclass(annotation, bool):
        return "bool"
    if issubclass(annotation, enum.Enum):
        return "text"
    if issubclass(annotation, str):
        return "text"
    if issubclass(annotation, int | float | Decimal):  # money is a Decimal (shown as "12.50")
        return "number"
    if issubclass(annotation, datetime | date):
        return "time"
    if issubclass(annotation, list | tuple | set):
        return "list"
    if issubclass(annotation, BaseModel | dict):
        return "record"
    return "any"


def matcher_problems(raw: Any, annotation: Any) -> Iterator[tuple[tuple[str, ...], str]]:
    """What keeps the matcher ``raw`` from applying to a field of type ``annotation``: (place, message)."""
    kind = kind_of(annotation)
    if not isinstance(raw, Mapping):
        return
    keys = [str(key) for key in raw]
    if not any(key in OPERATORS for key in keys):  # a mapping of field names
        if kind in _SCALARS:
            for key in keys:
                hint = did_you_mean(key, OPERATORS)
                yield (
                    (key,),
                    f"'{key}' is not an operator.{hint} (A mapping of names matches the fields of a "
                    f"record, and this field holds {_NOUNS[kind]}.) Operators: {', '.join(OPERATORS)}",
                )
        return
    for key, value in raw.items():
        name = str(key)
        operator = OPERATORS.get(name)
        if operator is None:
            continue  # a mapping that mixes operators and fields: the matcher does not compile
        allowed = _APPLIES_TO.get(operator.reads)
        if allowed is not None and kind not in allowed:
            yield (name,), f"'{name}' cannot apply here: this field holds {_NOUNS[kind]}"
        for nested in operator.nested(value) if operator.nested is not None else ():
            yield from matcher_problems(nested, annotation)
