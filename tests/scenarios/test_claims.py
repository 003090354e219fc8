"""Claimed acts: a text that says an act was done where no call of the episode did it."""

from __future__ import annotations

from datetime import UTC, datetime
from typing import Any

import pytest

from pare.scenarios.claims import claims, unbacked
from pare.sim.log import LogEntry

AT = datetime(2025, 3, 3, 9, 0, tzinfo=UTC)


@pytest.mark.parametrize(
    ("text", "acts"),
    [
        ("I've cancelled the cab, can you pick me up at 18:50?", ["cancelled"]),
        ("I've raised a dispute with my bank", ["disputed"]),
        ("We have now frozen the card", ["frozen"]),
        ("I just booked a table for four", ["booked"]),
        ("I have gone ahead and ordered the lamp", ["ordered"]),
        ("I've also sent over the extra $50", ["sent money"]),  # a payment, not a standing order
        ("I've updated the weekly reminder", ["changed"]),
        ("I've changed my mind", []),
        ("I've updated Tom", []),  # told him
        ("I've sent you the form", []),  # a message sends itself
        # not claims of a recent act
        ("Once I've paid I'll let you know", []),
        ("I've already paid this on the 3rd", []),
        ("the invoice INV-5170, which I have paid in full", []),
        ("I haven't paid yet", []),
        ("Have I paid?", []),
        ("I paid it last week", []),
        ("I'll cancel it tomorrow", []),
    ],
)
def test_a_first_person_claim_of_a_recent_act_is_read(text: str, acts: list[str]) -> None:
    assert [claim.act for claim in claims(text)] == acts


def _entry(index: int, actor: str, tool: str, args: dict[str, Any] | None = None) -> LogEntry:
    app, _, name = tool.partition("__")
    return LogEntry(index, 1, AT, actor, app, name, args or {}, "write", True)  # type: ignore[arg-type]


def test_a_claim_is_backed_by_a_call_that_does_the_act_by_anyone_but_not_by_its_own_message() -> None:
    message = _entry(5, "assistant", "messaging__send_message", {"content": "I've cancelled the order"})
    said = list(claims(message.args["content"]))
    assert unbacked(said, [message], message) == said  # the message itself cancels nothing
    by_hand = _entry(3, "user", "shopping__cancel_order", {"order_id": "o1"})
    assert unbacked(said, [by_hand, message], message) == []
    disputed = list(claims("I've raised a dispute with the bank"))
    assert unbacked(disputed, [by_hand, message], message) == disputed  # a cancel is no dispute


def test_money_sent_over_is_backed_by_a_payment_not_by_a_standing_order() -> None:
    message = _entry(5, "assistant", "email__send_email", {"content": "I've sent over the extra $50"})
    said = list(claims(message.args["content"]))
    order = _entry(3, "assistant", "banking__create_standing_order")
    assert unbacked(said, [order, message], message) == said
    paid = _entry(4, "assistant", "banking__pay_payee")
    assert unbacked(said, [order, paid, message], message) == []
