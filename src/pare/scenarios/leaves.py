"""The leaves of JSON-like data: one walk for the readers that look at every value of a state or a call."""

from __future__ import annotations

from collections.abc import Iterator, Mapping
from typing import Any


def leaves(value: Any, key: str = "") -> Iterator[tuple[str, Any]]:
    """``(the key it sits under, the value)`` for every leaf of a JSON-like ``value`` (mappings, lists and
    tuples read through; a list's items sit under the list's key).
    """
    if isinstance(value, Mapping):
        for inner, item in value.items():
            yield from leaves(item, str(inner))
    elif isinstance(value, list | tuple):
        for item in value:
            yield from leaves(item, key)
    else:
        yield key, value


def strings(value: Any) -> Iterator[str]:
    """Every string among the leaves of ``value``."""
    return (leaf for _, leaf in leaves(value) if isinstance(leaf, str))
