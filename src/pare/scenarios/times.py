"""Times in scenario files: absolute, or relative to the scenario's start.

Accepted forms:

* ``2025-03-03T09:05:00Z`` (or any ISO 8601 time; a time without a zone is UTC);
* ``+15m``, ``-2h``, ``+1d2h30m``: an offset from the start (``d``, ``h``, ``m``, ``s``);
* ``day+1 09:00``, ``day-2 18:30``, ``day 14:00``: a clock time on a day counted from the start's date.

Durations (event delays) are written ``10m``, ``1h30m``, ``45s`` or ``0``.
"""

from __future__ import annotations

import re
from collections.abc import Mapping
from datetime import UTC, date, datetime, timedelta
from typing import Any

_UNITS = {"d": "days", "h": "hours", "m": "minutes", "s": "seconds"}
_DURATION = re.compile(r"^(?:\d+[dhms])+$")
_PART = re.compile(r"(\d+)([dhms])")
_OFFSET = re.compile(r"^([+-])((?:\d+[dhms])+)$")
_DAY = re.compile(r"^day(?:\s*([+-])\s*(\d+))?\s+(\d{1,2}):(\d{2})(?::(\d{2}))?$")


_RELATIVE_STARTS = frozenset("+-d")
_PLAIN_LEAVES = frozenset({int, float, bool, type(None)})
"""Types of seed values that are never times: left as they are."""


class TimeFormatError(ValueError):
    """A time or duration that cannot be read; the message says which forms are accepted."""


def parse_duration(text: str | int | float | timedelta) -> timedelta:
    """``10m``, ``1h30m``, ``2d``, ``45s``, ``0`` (or a number of seconds) as a :class:`timedelta`."""
    if isinstance(text, timedelta):
        return text
    if isinstance(text, bool):
        raise TimeFormatError(f"{text!r} is not a duration")
    if isinstance(text, int | float):
        if text < 0:
            raise TimeFormatError(f"a duration cannot be negative, got {text}")
        return timedelta(seconds=text)
    compact = text.replace(" ", "")
    if compact == "0":
        return timedelta(0)
    if not _DURATION.match(compact):
        raise TimeFormatError(f"'{text}' is not a duration; write e.g. 10m, 1h30m, 2d or 45s")
    return _sum_parts(compact)


def _sum_parts(text: str) -> timedelta:
    total = timedelta(0)
    for amount, unit in _PART.findall(text):
        total += timedelta(**{_UNITS[unit]: int(amount)})
    return total


def is_relative_time(text: str) -> bool:
    """Whether ``text`` is written relative to the start (``+15m``, ``day+1 09:00``)."""
    # Both forms begin with "+", "-" or "day": most text (every string of the seed data is asked) is
    # told apart by its first character, without stripping or matching.
    first = text[:1]
    if first not in _RELATIVE_STARTS and not (first.isspace() and text.lstrip()[:1] in _RELATIVE_STARTS):
        return False
    stripped = text.strip()
    return bool(_OFFSET.match(stripped.replace(" ", "")) or _DAY.match(stripped))


def parse_time(text: str | datetime, start: datetime) -> datetime:
    """A time in any accepted form, resolved against ``start``; always timezone-aware (UTC)."""
    if isinstance(text, datetime):
        return text if text.tzinfo else text.replace(tzinfo=UTC)
    stripped = text.strip()
    offset = _OFFSET.match(stripped.replace(" ", ""))
    if offset:
        delta = _sum_parts(offset.group(2))
        return start - delta if offset.group(1) == "-" else start + delta
    day = _DAY.match(stripped)
    if day:
        sign, days, hour, minute, second = day.groups()
        shift = int(days or 0) * (-1 if sign == "-" else 1)
        if int(hour) > 23 or int(minute) > 59 or int(second or 0) > 59:
            raise TimeFormatError(f"'{text}' has an impossible clock time")
        base = start.replace(hour=int(hour), minute=int(minute), second=int(second or 0), microsecond=0)
        return base + timedelta(days=shift)
    try:
        moment = datetime.fromisoformat(stripped.replace("Z", "+00:00"))
    except ValueError:
        raise TimeFormatError(
            f"'{text}' is not a time; write an ISO time (2025-03-03T09:05:00Z), an offset from the start "
            "(+15m, -2h, +1d2h) or a day and clock time (day+1 09:00)"
        ) from None
    return moment if moment.tzinfo else moment.replace(tzinfo=UTC)


def resolve_relative_times(data: Any, start: datetime) -> Any:
    """``data`` with every string written as a relative time replaced by its ISO form.

    Used on seed data and tool arguments, so an email can be "received" at ``-2h`` and a meeting start at
    ``day+1 10:00``. Only whole strings in a relative form are touched; other text is left alone. Dates and
    times YAML read as such (an unquoted ``2026-04-23T09:00:00Z``) become ISO text too (UTC when written
    without a zone), so the arguments recorded in the log and the trajectory are JSON.
    """
    # Seed data is a tree of plain dicts, lists, strings and numbers, walked whole for the first episode of
    # every scenario: those are told by their exact type, the rest by the checks below.
    kind = type(data)
    if kind is str:
        return parse_time(data, start).isoformat() if is_relative_time(data) else data
    if kind is dict:
        return {key: resolve_relative_times(value, start) for key, value in data.items()}
    if kind is list:
        return [resolve_relative_times(value, start) for value in data]
    if kind in _PLAIN_LEAVES:
        return data
    if isinstance(data, str):
        return parse_time(data, start).isoformat() if is_relative_time(data) else data
    if isinstance(data, datetime):  # YAML reads an unquoted timestamp as one: arguments stay JSON text
        return (data if data.tzinfo else data.replace(tzinfo=UTC)).isoformat()
    if isinstance(data, date):
        return data.isoformat()
    if isinstance(data, Mapping):
        return {key: resolve_relative_times(value, start) for key, value in data.items()}
    if isinstance(data, list):
        return [resolve_relative_times(value, start) for value in data]
    return data
