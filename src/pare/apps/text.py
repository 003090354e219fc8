"""Text shared by the apps: tidying what actors type (so every app treats blank and repeated input alike)
and shortening what screens display (so every list row looks alike).
"""

from __future__ import annotations

from collections.abc import Iterable
from datetime import datetime


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


PAGE = 5
"""How many items a list screen displays when the user arrives on it: a phone's first page, not the list."""


def preview(text: str | None, limit: int = 60) -> str:
    """``text`` on one line, cut at a word boundary to at most about ``limit`` characters, with "…".

    What a phone's list row shows of a message or a note: enough to recognise it, not the whole text.
    """
    flat = " ".join((text or "").split())
    if len(flat) <= limit:
        return flat
    cut = flat[:limit].rsplit(" ", 1)[0] or flat[:limit]
    return cut.rstrip(",;:.-") + "…"


def short_time(moment: datetime | None) -> str | None:
    """``moment`` as a list row shows it, e.g. ``2025-03-03 09:00`` (the simulation's zone, UTC)."""
    return None if moment is None else f"{moment:%Y-%m-%d %H:%M}"
