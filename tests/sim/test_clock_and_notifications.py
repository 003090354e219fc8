from __future__ import annotations

from datetime import UTC, datetime, timedelta

import pytest

from pare.errors import SimulationBug
from pare.sim import NotificationCenter, NotificationPolicy, SimClock
from pare.sim.notifications import truncate_words

T0 = datetime(2025, 3, 3, 9, 0, tzinfo=UTC)
BODY = (
    "Hi Sam, the plumber can come on Thursday at 3pm but needs someone to let him in. "
    "Can you confirm by tonight?"
)


def test_clock_moves_only_forward() -> None:
    clock = SimClock(datetime(2025, 3, 3, 9, 0))  # naive means UTC
    assert clock.now == T0
    clock.advance(timedelta(minutes=5))
    clock.advance_to(T0)  # the past leaves it where it is
    assert clock.now == T0 + timedelta(minutes=5)
    assert clock.elapsed == timedelta(minutes=5)
    with pytest.raises(SimulationBug):
        clock.advance(timedelta(seconds=-1))


def post(center: NotificationCenter) -> None:
    center.post(
        time=T0,
        app="Email",
        kind="new_email",
        headline="New email from Bob Okafor",
        subject="Plumber visit",
        body=BODY,
        data={"email_id": "email-7"},
    )


def test_user_copy_is_truncated_like_a_phone_assistant_copy_is_full() -> None:
    center = NotificationCenter()
    post(center)
    user = center.take_unread("user")
    assistant = center.take_unread("assistant")
    assert user == [
        "[2025-03-03 09:00] Email: New email from Bob Okafor — Plumber visit: "
        "Hi Sam, the plumber can come on Thursday at 3pm but needs …"
    ]
    assert BODY in assistant[0] and "email_id=email-7" in assistant[0]
    assert "email_id" not in user[0]


@pytest.mark.parametrize(
    ("policy", "user_text"),
    [
        (NotificationPolicy(user="minimal"), "[2025-03-03 09:00] Email: New email from Bob Okafor"),
        (
            NotificationPolicy(user="preview", preview_words=3),
            "[2025-03-03 09:00] Email: New email from Bob Okafor — Plumber visit: Hi Sam, the …",
        ),
    ],
)
def test_detail_level_is_configurable(policy: NotificationPolicy, user_text: str) -> None:
    center = NotificationCenter(policy)
    post(center)
    assert center.take_unread("user") == [user_text]


def test_each_recipient_has_its_own_read_position() -> None:
    center = NotificationCenter()
    post(center)
    assert len(center.take_unread("user")) == 1
    post(center)
    assert len(center.take_unread("user")) == 1
    assert len(center.take_unread("assistant")) == 2
    assert center.take_unread("assistant") == []
    assert center.inboxes["user"].read_position == 2


def test_truncate_words() -> None:
    assert truncate_words("one two three", 3) == "one two three"
    assert truncate_words("one  two\nthree four", 2) == "one two …"


def test_log_entry_names_the_app_and_screen_of_a_user_call() -> None:
    from tests.conftest import make_env, ok

    env = make_env(["contacts"])
    ok(env.call("user", "open_app", {"app_name": "contacts"}))
    ok(env.call("user", "list_contacts"))
    assert [e.app_screen for e in env.log] == [None, ("contacts", "List")]
    ok(env.call("assistant", "contacts__get_contacts", {}, mode="observe"))
    assert env.log[-1].app_screen is None
