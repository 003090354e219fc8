"""How bad a wrong call of a write tool is: each app classes its write tools by it (``App.harm``)."""

from __future__ import annotations

from typing import Literal

Harm = Literal["reversible", "costly", "irreversible"]
"""``reversible``: undone by one call (a calendar event, a frozen card); ``costly``: undone only at a cost
or with someone else's help (an order, a cancellation, a dispute); ``irreversible``: cannot be undone (a
payment, a sent message, a deletion)."""
