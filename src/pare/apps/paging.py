"""Pages of lists: how much a page shows of how many, and how to see the rest.

A model that sees five rows and no sign of more takes them for the list. Every page a tool returns and
every list a screen displays says how much it shows (``showing``), so that a partial list reads as one.
"""

from __future__ import annotations

from typing import Any, ClassVar

from pydantic import BaseModel, Field, model_validator

from pare.apps.text import PAGE

__all__ = ["PAGE", "Paged", "showing", "showing_screen"]


def showing(offset: int, shown: int, total: int, rest: str = "offset={offset}") -> str:
    """How much of a list of ``total`` a page of ``shown`` rows from ``offset`` shows, and how to see more.

    ``rest`` says how to ask for the rows after the page, with ``{offset}`` standing for where they start,
    e.g. ``"list_emails(offset={offset})"``. Examples: ``"all 3"``, ``"1-5 of 11; offset=5 shows the
    next"``, ``"6-11 of 11 (the last)"``.
    """
    if offset == 0 and shown >= total:
        return f"all {total}"
    if shown == 0:
        return f"none of {total}: offset {offset} is past the end; {rest.format(offset=0)} shows the first"
    last = offset + shown
    text = f"{offset + 1}-{last} of {total}"
    if last < total:
        # a way that takes no offset (a tool that lists everything) shows the whole list, not the next page
        rest_of_it = "shows the next" if "{offset}" in rest else "shows them all"
        return f"{text}; {rest.format(offset=last)} {rest_of_it}"
    return f"{text} (the last)"


def showing_screen(rows: list[Any], total: int, rest: str) -> dict[str, Any]:
    """The ``showing`` entry of a list screen that displays ``rows`` of ``total`` (its first page), or
    nothing when it displays them all; ``rest`` is the user action that shows more, as for :func:`showing`,
    e.g. ``"list_emails(offset={offset})"``.
    """
    if len(rows) >= total:
        return {}
    return {"showing": showing(0, len(rows), total, rest)}


class Paged(BaseModel):
    """A page of a list returned by a tool: subclasses name their rows' field in ``rows_field``."""

    rows_field: ClassVar[str]
    total_field: ClassVar[str] = "total"

    showing: str = Field(
        default="",
        description='how much of the list this page shows and how to see the rest, e.g. "1-5 of 11; '
        'offset=5 shows the next"',
    )

    @model_validator(mode="after")
    def _say_how_much(self) -> Paged:
        if not self.showing:
            rows = getattr(self, self.rows_field)
            self.showing = showing(getattr(self, "offset", 0), len(rows), getattr(self, self.total_field))
        return self
