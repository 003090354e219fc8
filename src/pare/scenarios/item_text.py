"""An item's text is all its text: what a state check's ``_text`` reads.

Where the words of an item go is the writer's choice: "Dentist" as a calendar event's title, or
"Check-up" with "dentist, Dr. Haddad" in its description; a reminder's title or its description; a note's
title or its body. A check that names a field (``title``) reads that field alone; ``_text`` reads every
text field the item has, in the order below, one per line (so each is its own sentence for the text
matchers).
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

TEXT_FIELDS: tuple[str, ...] = ("title", "subject", "description", "content", "notes", "location")
"""The fields of an item that ``_text`` reads, where it has them: calendar events (title, description,
location), reminders (title, description), notes (title, content), emails (subject, content), contacts
(notes)."""


def item_text(record: Mapping[str, Any]) -> str | None:
    """Every text field of ``record`` that holds text, one per line; ``None`` when it has none."""
    parts = [value for name in TEXT_FIELDS if isinstance(value := record.get(name), str) and value.strip()]
    return "\n".join(parts) if parts else None


def has_text_fields(fields: Mapping[str, Any]) -> bool:
    """Whether an item with these fields (name to type) has a field that ``_text`` reads."""
    return any(name in fields for name in TEXT_FIELDS)
