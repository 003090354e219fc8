"""What observe mode hands execute mode: the items it read and the ids it saw, bounded in size.

Execute mode starts a fresh conversation for an accepted task. Without a handover it would know only the
proposal and the user's answer, and would spend its actions looking up again the emails, events,
conversations and products observe mode had already read. The handover collects, from observe mode's
read results, every record that carries an id (``email_id``, ``item_id``, ``id`` ...) with its short
fields (subject, sender, name, price, start time ...), and, from the user's actions observe mode was
shown, the ids in their arguments. The newest sighting of an item wins, and only the newest
``max_items`` are kept, each line at most ``max_line`` characters: the handover stays small whatever the
episode read.
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping
from dataclasses import dataclass, field
from typing import Any

from pare.sim.log import LogEntry

HANDOVER_HEADING = (
    "Items you read while observing, with their ids (newest last; read again only what may have "
    "changed or is missing):"
)
"""The heading of the handover in execute mode's first message."""

_LABELS = ("name", "title", "subject", "content")
"""The fields that name a record best, in order: a nested record says which record it is inside by these."""


def is_id_key(key: str) -> bool:
    """Whether ``key`` names an id: ``id``, or ending in ``_id`` (``email_id``, ``item_id``)."""
    return key == "id" or key.endswith("_id")


def _short(value: Any, width: int) -> str | None:
    """A scalar field as the handover writes it (long text cut), or ``None`` for lists and records."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int | float):
        return str(value)
    if isinstance(value, str):
        text = " ".join(value.split())
        return text if len(text) <= width else text[: width - 1] + "…"
    return None


def _label(record: Mapping[str, Any]) -> str:
    """A record's ids and best name, as a nested record names what it is inside."""
    parts = [str(value) for key, value in record.items() if is_id_key(key) and isinstance(value, str | int)]
    name = next((record[key] for key in _LABELS if isinstance(record.get(key), str)), None)
    if name is not None:
        parts.append(_short(name, 40) or "")
    return " ".join(parts)


def records_with_ids(value: Any, parent: str = "") -> Iterator[tuple[tuple[str, ...], str]]:
    """Every record in a JSON-ready ``value`` that carries an id: its ids (its key) and its line.

    A record's line holds its scalar fields, text cut to 60 characters; lists and records inside it are
    walked on their own, each line saying which record it is inside (``in prod-mug Ceramic Mug``).
    """
    if isinstance(value, list):
        for element in value:
            yield from records_with_ids(element, parent)
        return
    if not isinstance(value, Mapping):
        return
    ids = tuple(
        f"{key}={item}" for key, item in value.items() if is_id_key(key) and isinstance(item, str | int)
    )
    if ids:
        fields = []
        for key, item in value.items():
            text = _short(item, 60)
            if text is not None and text != "":
                fields.append(f"{key}={text}")
        line = ", ".join(fields) + (f" (in {parent})" if parent else "")
        yield ids, line
    inner = _label(value) if ids else parent
    for item in value.values():
        if isinstance(item, list | Mapping):
            yield from records_with_ids(item, inner)


@dataclass
class Handover:
    """The items observe mode read and the ids it saw this episode, newest last, bounded."""

    max_items: int = 40
    max_line: int = 200
    _lines: dict[tuple[str, ...], str] = field(default_factory=dict)
    """Each item's line under its ids; insertion order is recency (a new sighting moves it to the end)."""

    def clear(self) -> None:
        """Forget everything (a new episode)."""
        self._lines.clear()

    def read(self, entry: LogEntry) -> None:
        """Keep the records with ids in a successful read's result (other calls are not reads)."""
        if entry.ok and entry.kind == "read":
            for ids, line in records_with_ids(entry.result):
                self._keep(ids, f"{entry.app}.{entry.tool}: {line}")

    def saw(self, entry: LogEntry) -> None:
        """Keep the ids in the arguments of a call observe mode was shown (a user's action)."""
        ids = tuple(
            f"{key}={value}" for key, value in entry.args.items() if is_id_key(key) and isinstance(value, str)
        )
        if ids and entry.ok:
            self._keep(ids, f"the user's {entry.app}.{entry.tool}: {', '.join(ids)}", replace=False)

    def _keep(self, ids: tuple[str, ...], line: str, *, replace: bool = True) -> None:
        known = self._lines.pop(ids, None)
        # a user's action names an item by id only: a line that also holds its fields is worth more
        self._lines[ids] = known if known is not None and not replace else line
        while len(self._lines) > self.max_items:
            del self._lines[next(iter(self._lines))]

    def render(self) -> str:
        """The handover as execute mode's first message shows it, or ``""`` when nothing was read."""
        if not self._lines:
            return ""
        lines = [
            line if len(line) <= self.max_line else line[: self.max_line - 1] + "…"
            for line in self._lines.values()
        ]
        return "\n".join([HANDOVER_HEADING, *(f"- {line}" for line in lines)])
