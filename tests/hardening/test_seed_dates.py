"""Seed records that say they already happened must not be dated after the episode's start.

Such a record would later be edited "before it existed" (a note updated at 09:00 that was created at
10:00, an order cancelled before it was placed), leaving state that fails its own validation. The
loader refuses them up front, naming each record.
"""

from __future__ import annotations

from typing import Any

import pytest

from pare.errors import UserInputError
from tests.conftest import make_env, ok

LATE = "2025-03-03T10:00:00Z"  # an hour after the tests' start, 2025-03-03 09:00
EARLY = "2025-03-02T18:00:00Z"

ORDER = {
    "order_id": "o-1",
    "items": [
        {"item_id": "i-1", "product_name": "Mug", "variant_name": "Blue", "unit_price": 8.0, "quantity": 1}
    ],
    "subtotal": 8.0,
    "total": 8.0,
}
RIDE = {
    "ride_id": "r-1",
    "start_location": "Home",
    "end_location": "Work",
    "service_type": "Default",
    "pickup_time": "2025-03-02T19:00:00Z",
    "distance_km": 5.0,
    "duration_minutes": 12,
    "price": 11.0,
    "status": "completed",
}


def seeds(stamp: str) -> list[tuple[str, dict[str, Any], str]]:
    return [
        (
            "notes",
            {"notes": {"n-1": {"note_id": "n-1", "title": "Plan", "created_at": EARLY, "updated_at": stamp}}},
            "note 'n-1'",
        ),
        (
            "email",
            {"emails": {"e-1": {"email_id": "e-1", "sender": "a@x.org", "timestamp": stamp}}},
            "email 'e-1'",
        ),
        (
            "messaging",
            {
                "users": {"u-1": "Ana"},
                "conversations": {
                    "c-1": {
                        "conversation_id": "c-1",
                        "participant_ids": ["user-me", "u-1"],
                        "messages": [
                            {"message_id": "m-1", "sender_id": "u-1", "content": "hi", "timestamp": stamp}
                        ],
                    }
                },
            },
            "message 'm-1' of conversation 'c-1'",
        ),
        ("shopping", {"orders": {"o-1": {**ORDER, "placed_at": stamp}}}, "order 'o-1'"),
        ("cab", {"rides": {"r-1": {**RIDE, "booked_at": stamp}}}, "ride 'r-1'"),
        (
            "banking",
            {
                "accounts": {"a-1": {"account_id": "a-1", "name": "Everyday", "balance": 10}},
                "transactions": {
                    "t-1": {
                        "transaction_id": "t-1",
                        "account_id": "a-1",
                        "amount": -2,
                        "description": "Cafe",
                        "booked_at": stamp,
                    }
                },
            },
            "transaction 't-1'",
        ),
    ]


@pytest.mark.parametrize(("app", "data", "named"), seeds(LATE), ids=lambda v: v if isinstance(v, str) else "")
def test_a_record_dated_after_the_start_is_refused_by_name(
    app: str, data: dict[str, Any], named: str
) -> None:
    with pytest.raises(UserInputError) as raised:
        make_env([app], {app: data})
    message = str(raised.value)
    assert f"seed data of app '{app}'" in message
    assert "dated after the episode's start (2025-03-03 09:00)" in message
    assert named in message and "2025-03-03 10:00" in message


@pytest.mark.parametrize(
    ("app", "data", "named"), seeds(EARLY), ids=lambda v: v if isinstance(v, str) else ""
)
def test_records_dated_before_the_start_load(app: str, data: dict[str, Any], named: str) -> None:
    make_env([app], {app: data})


def test_a_seeded_note_edited_during_the_episode_stays_valid() -> None:
    """What the refusal protects: the edit stamps the note at the clock's time, after its creation."""
    env = make_env(["notes"], {"notes": seeds(EARLY)[0][1]})
    ok(env.call("assistant", "notes__update_note", {"note_id": "n-1", "content": "new"}, mode="execute"))
    note = env.app("notes").state.notes["n-1"]
    assert note.updated_at >= note.created_at
    type(env.app("notes").state).model_validate(env.app("notes").snapshot())


@pytest.mark.parametrize(("app", "data", "named"), seeds(LATE), ids=lambda v: v if isinstance(v, str) else "")
def test_each_late_record_says_where_its_date_is(app: str, data: dict[str, Any], named: str) -> None:
    """The scenario loader turns the location into the file's line: it must lead to the late date."""
    loaded = make_env([app]).app(app)
    late = type(loaded.state).model_validate(data)
    loaded.adopt(late)
    (record,) = loaded.records_dated_after(loaded.ctx.now())
    assert named in str(record)
    value: Any = late.model_dump(mode="json")
    for part in record.location:
        value = value[part]
    assert value.startswith("2025-03-03T10:00")
