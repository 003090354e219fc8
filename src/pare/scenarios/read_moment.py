"""When a reminder the assistant wrote is read, for its relative days ("tomorrow", "tonight", "Sunday").

A message is read when it is sent. A reminder is read twice: when it is written and when it fires. "Entries
close tomorrow, Sunday" in a reminder written on Tuesday and due on Saturday speaks as of Saturday; "the
doctor wants to see you in six weeks" in the same reminder speaks as of Tuesday. A reminder's text is
therefore read both ways, and a reading that holds in either is taken: :func:`fires_at` gives the second
moment.
"""

from __future__ import annotations

from collections.abc import Mapping
from datetime import datetime
from typing import Any

from pare.scenarios.times import TimeFormatError, parse_time
from pare.sim.log import LogEntry

DUE_FIELD = "due_datetime"
"""The field of an item that says when it fires (a reminder's)."""


def _moment(value: Any, anchor: datetime) -> datetime | None:
    if isinstance(value, datetime):
        return value
    if not isinstance(value, str) or len(value) < 10:
        return None
    try:
        return parse_time(value, anchor)
    except TimeFormatError:
        return None


def due_moment(fields: Mapping[str, Any], written: datetime) -> datetime | None:
    """When an item with ``fields`` (a record, or a call's arguments, its ``updates`` too) fires, when it
    has a due time later than ``written``; else ``None``.
    """
    due = _moment(fields.get(DUE_FIELD), written)
    if due is None:
        updates = fields.get("updates")
        due = _moment(updates.get(DUE_FIELD), written) if isinstance(updates, Mapping) else None
    if due is None:
        return None
    if due.tzinfo is None and written.tzinfo is not None:
        due = due.replace(tzinfo=written.tzinfo)
    return due if due > written else None


def fires_at(entry: LogEntry) -> datetime | None:
    """When the reminder a call wrote fires (its second reading moment); ``None`` for any other call."""
    return due_moment(entry.args, entry.time) if entry.app == "reminder" else None
