"""A repeating item is each of its occurrences: what a state check that forbids a due time reads.

A reminder set daily from Tuesday 18:30 with no end rings on Tuesday, and also on Thursday and every day
after. Its record shows only the next occurrence (``due_datetime``), so a check that no reminder rings on
Thursday ("count: 0" of those due outside a window) would read Tuesday and let it pass. Where a check
forbids items, a repeating one is read as three: as it is (the next occurrence), the occurrence after
that, and the last one (the last before ``repeat_until``; an endless series has none, read as one far
beyond any story). The three bound every occurrence between them for the day windows checks use, so an
item is forbidden when one of them is. Checks that want items keep reading the record as it is.
"""

from __future__ import annotations

from collections.abc import Mapping
from datetime import UTC, datetime, timedelta
from typing import Any

from pare.apps.reminder import Repetition, next_occurrence

DUE_FIELD = "due_datetime"
"""The field a repetition moves."""

ENDLESS = timedelta(days=365 * 100)
"""How far beyond its first occurrence an endless series is read as still ringing."""

_MOST_STEPS = 40_000
"""A bound on the walk to the last occurrence before ``repeat_until`` (a century of daily ones)."""


def occurrence_records(record: Mapping[str, Any]) -> tuple[Mapping[str, Any], ...]:
    """``record`` as it is and, for a repeating one, as its next and its last occurrence (see the module)."""
    repetition = _repetition(record.get("repetition"))
    due = _moment(record.get(DUE_FIELD))
    if repetition is None or repetition == Repetition.NONE or due is None:
        return (record,)
    following = next_occurrence(due, repetition, due)
    until = _moment(record.get("repeat_until"))
    last = _last(due, repetition, until) if until is not None else due + ENDLESS
    views, seen = [record], {due}
    for moment in (following, last):
        if moment is not None and moment not in seen and (until is None or moment <= until):
            seen.add(moment)
            views.append({**record, DUE_FIELD: moment.isoformat()})
    return tuple(views)


def _last(due: datetime, repetition: Repetition, until: datetime) -> datetime:
    """The last occurrence not after ``until``."""
    current = due
    for _ in range(_MOST_STEPS):
        following = next_occurrence(due, repetition, current)
        if following is None or following > until:
            return current
        current = following
    return current


def _repetition(value: Any) -> Repetition | None:
    if not isinstance(value, str):
        return None
    try:
        return Repetition(value)
    except ValueError:
        return None


def _moment(value: Any) -> datetime | None:
    if isinstance(value, datetime):
        return value if value.tzinfo else value.replace(tzinfo=UTC)
    if not isinstance(value, str):
        return None
    try:
        moment = datetime.fromisoformat(value)
    except ValueError:
        return None
    return moment if moment.tzinfo else moment.replace(tzinfo=UTC)
