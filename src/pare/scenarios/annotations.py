"""Walking type annotations of the state and scenario models: how paths in a document are checked."""

from __future__ import annotations

import types
import typing
from typing import Any

from pydantic import BaseModel


def strip_optional(annotation: Any) -> Any:
    """``X | None`` as ``X``; of a union holding a model (``int | Count | None``), the model."""
    if typing.get_origin(annotation) not in (typing.Union, types.UnionType):
        return annotation
    options = [arg for arg in typing.get_args(annotation) if arg is not type(None)]
    models = [option for option in options if isinstance(option, type) and issubclass(option, BaseModel)]
    if len(options) == 1:
        return options[0]
    return models[0] if models else annotation


def model_fields(annotation: Any) -> dict[str, Any] | None:
    """Field name to annotation when ``annotation`` is (optionally) a pydantic model, else ``None``."""
    model = strip_optional(annotation)
    if isinstance(model, type) and issubclass(model, BaseModel):
        return {name: info.annotation for name, info in model.model_fields.items()}
    return None


def item_type(annotation: Any) -> Any:
    """The item type of ``dict[str, X]`` or ``list[X]`` (optionally ``| None``); ``None`` otherwise."""
    annotation = strip_optional(annotation)
    origin = typing.get_origin(annotation)
    args = typing.get_args(annotation)
    if origin is dict and len(args) == 2:
        return args[1]
    if origin is list and args:
        return args[0]
    return None


def step_into(annotation: Any, part: str | int) -> Any:
    """The annotation one step down a document path: a model's field, a dict's value, a list's item;
    ``None`` when there is no such step.
    """
    fields = model_fields(annotation)
    if fields is not None:
        return fields.get(str(part))
    return item_type(annotation)
