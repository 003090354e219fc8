"""The seed data format of an app, as scenario authors write it, generated from the app's state model.

So that the format shown to authors (``pare apps show APP --seed``) can never drift from what the loader
accepts: every field with its type, default and description, nested records spelled out, collections
keyed by id shown as the lists scenario files may write them as.
"""

from __future__ import annotations

import typing
from collections.abc import Iterator
from datetime import datetime
from enum import Enum
from typing import Any

from pydantic import BaseModel
from pydantic.fields import FieldInfo
from pydantic_core import PydanticUndefined

from pare.apps.registry import get_app_class
from pare.apps.tools import type_name
from pare.scenarios.annotations import item_type, model_fields, strip_optional
from pare.scenarios.seed import keyed_by

TIME_NOTE = "a time: ISO, an offset from the start (-2h, +15m) or a day and clock time (day+1 09:00)"


def seed_format(app: str) -> list[str]:
    """The lines describing ``app``'s seed data, as YAML-like text with comments."""
    state = get_app_class(app).State
    lines = ["seed:", f"  {app}:"]
    lines.extend(_fields(state, indent=4, top=True))
    return lines


def _fields(model: type[BaseModel], indent: int, *, top: bool = False) -> Iterator[str]:
    pad = " " * indent
    for name, info in model.model_fields.items():
        annotation = info.annotation
        notes = _notes(info, annotation)
        id_field = keyed_by(annotation) if top else None  # only the app's own collections may be lists
        items = item_type(annotation)
        record = _record(items) if items is not None else None
        nested = _record(annotation)
        if record is not None:
            if id_field is not None:
                what = f"a list of {record.__name__}, each with its {id_field} (or a mapping by id)"
            elif typing.get_origin(strip_optional(annotation)) is list:
                what = f"a list of {record.__name__}"
            else:
                what = f"a mapping from id to {record.__name__}"
            yield f"{pad}{name}:{_comment([what, *notes])}"
            if what.startswith("a mapping"):
                yield f"{pad}  <id>:"
                yield from _fields(record, indent + 4)
            else:
                yield from _list_item(record, indent + 2)
        elif nested is not None:
            yield f"{pad}{name}:{_comment(notes)}"
            yield from _fields(nested, indent + 2)
        else:
            yield f"{pad}{name}: {_type(annotation)}{_comment(notes)}"


def _comment(parts: list[str]) -> str:
    return f"  # {'; '.join(parts)}" if parts else ""


def _list_item(model: type[BaseModel], indent: int) -> Iterator[str]:
    lines = list(_fields(model, indent + 2))
    if lines:
        first = lines[0]
        yield " " * indent + "- " + first.lstrip()
        yield from lines[1:]


def _record(annotation: Any) -> type[BaseModel] | None:
    fields = model_fields(annotation)
    if fields is None:
        return None
    model = strip_optional(annotation)
    return model if isinstance(model, type) and issubclass(model, BaseModel) else None


def _type(annotation: Any) -> str:
    text = type_name(annotation)
    return text.replace("datetime", "time")


def _notes(info: FieldInfo, annotation: Any) -> list[str]:
    parts = []
    if info.is_required() and not _filled_in(info):
        parts.append("required")
    elif info.default is not PydanticUndefined and info.default not in (None, [], {}, ""):
        default = info.default.value if isinstance(info.default, Enum) else info.default
        parts.append(f"default {default!r}")
    if _mentions_time(annotation):
        parts.append(TIME_NOTE)
    if info.description:
        parts.append(info.description)
    return parts


def _filled_in(info: FieldInfo) -> bool:
    """Whether a field without a default is filled in by its model when left out (it says so with
    ``json_schema_extra={"optional": True}``; its description says with what).
    """
    extra = info.json_schema_extra
    return isinstance(extra, dict) and extra.get("optional") is True


def _mentions_time(annotation: Any) -> bool:
    annotation = strip_optional(annotation)
    if typing.get_origin(annotation) is typing.Annotated:
        annotation = typing.get_args(annotation)[0]
    return isinstance(annotation, type) and issubclass(annotation, datetime)
