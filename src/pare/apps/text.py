"""Tidying what actors type: shared by the apps so every app treats blank and repeated input alike."""

from __future__ import annotations

from collections.abc import Iterable


def optional_text(value: str | None) -> str | None:
    """``value`` stripped; blank text counts as no text."""
    if value is None:
        return None
    return value.strip() or None


def unique_names(names: Iterable[str]) -> list[str]:
    """Names stripped, blanks dropped, repeats (ignoring case) dropped, first spelling and order kept."""
    cleaned: list[str] = []
    seen: set[str] = set()
    for name in names:
        name = name.strip()
        if name and name.casefold() not in seen:
            seen.add(name.casefold())
            cleaned.append(name)
    return cleaned
