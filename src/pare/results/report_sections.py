"""The sections a report can show: a module of its own so the command line can list them cheaply."""

from __future__ import annotations

SECTIONS: tuple[str, ...] = (
    "main",
    "decisions",
    "resolution",
    "reliability",
    "consistency",
    "simulator",
    "cost",
    "kinds",
    "apps",
    "tags",
    "difficulty",
    "coverage",
)
"""Every section a report can show, in the order it shows them."""
