"""Seed data as written in scenario files, made ready for an app's ``State``.

Two conveniences over the raw state format:

* relative times (``-2h``, ``day+1 09:00``) anywhere in the data become ISO times;
* a collection the app keys by id (``emails``, ``events``, ``contacts`` ...) may be written as a list;
  each item's id field (``email_id``, ``event_id`` ...; ``code`` for discount codes) becomes its key.
"""

from __future__ import annotations

import functools
import typing
from collections.abc import Mapping
from datetime import datetime
from typing import Any

from pydantic import BaseModel

from pare.apps.registry import get_app_class
from pare.scenarios.annotations import item_type, model_fields, strip_optional
from pare.scenarios.times import resolve_relative_times

Location = tuple[str | int, ...]


class SeedError(ValueError):
    """Seed data that cannot be put in the app's format; ``location`` is where in the app's data."""

    def __init__(self, location: Location, message: str) -> None:
        super().__init__(message)
        self.location = location


def prepare_seed(
    app: str, data: Mapping[str, Any], start: datetime
) -> tuple[dict[str, Any], dict[Location, Location]]:
    """``data`` in the app's state format, and a map from locations in the result back to the file's.

    The map only holds entries for items that moved (list items now stored under their ids).
    """
    keyed_fields = _keyed_fields(get_app_class(app).State)
    prepared: dict[str, Any] = dict(resolve_relative_times(dict(data), start))
    moved: dict[Location, Location] = {}
    for name, id_field in keyed_fields:
        value = prepared.get(name)
        if not isinstance(value, list):
            continue
        keyed: dict[str, Any] = {}
        for index, item in enumerate(value):
            key = item.get(id_field) if isinstance(item, Mapping) else None
            if not isinstance(key, str):
                raise SeedError((name, index), f"each item of '{name}' needs its '{id_field}'")
            if key in keyed:
                raise SeedError((name, index, id_field), f"two items of '{name}' have the id '{key}'")
            keyed[key] = item
            moved[(name, key)] = (name, index)
        prepared[name] = keyed
    return prepared, moved


@functools.cache
def _keyed_fields(state_model: type[BaseModel]) -> tuple[tuple[str, str], ...]:
    """The fields of an app's state that key records by id, each with the records' id field, in the
    state's order: read from the class once (every episode's seed is prepared with them).
    """
    found = ((name, keyed_by(info.annotation)) for name, info in state_model.model_fields.items())
    return tuple((name, id_field) for name, id_field in found if id_field is not None)


def original_location(location: Location, moved: Mapping[Location, Location]) -> Location:
    """A location in prepared data translated back to where it was written."""
    if len(location) >= 2 and location[:2] in moved:
        return (*moved[location[:2]], *location[2:])
    return location


def keyed_by(annotation: Any) -> str | None:
    """For ``dict[str, Model]`` where ``Model`` has an ``*_id`` field (or a ``code``): that field's name."""
    if typing.get_origin(strip_optional(annotation)) is not dict:
        return None
    fields = list(model_fields(item_type(annotation)) or [])
    return next((name for name in fields if name.endswith("_id")), "code" if "code" in fields else None)
