from __future__ import annotations

from datetime import timedelta

from pare.apps.registry import app_names
from pare.apps.sample_data import START, sample_world
from pare.env import Environment
from tests.conftest import make_env, ok

APPS = app_names()


def test_snapshot_covers_every_app_and_diff_names_each_change() -> None:
    env = make_env(APPS, sample_world(), start_time=START)
    before = env.snapshot()
    assert set(before) == {"agent_ui", "files", *app_names()}
    # the nine apps with screens of the paper, plus Banking (beyond the paper); with Files, eleven
    assert len(app_names()) == 10
    assert "system" not in before and "system" in env.snapshot(include_navigation=True)
    ok(
        env.call(
            "assistant",
            "contacts__edit_contact",
            {"contact_id": "contact-bob", "updates": {"phone": "+1 555 9999"}},
            mode="execute",
        )
    )
    ok(env.call("assistant", "calendar__delete_calendar_event", {"event_id": "event-09"}, mode="execute"))
    changes = Environment.diff(before, env.snapshot())
    assert {
        "op": "replace",
        "path": "/contacts/contacts/contact-bob/phone",
        "value": "+1 555 9999",
    } in changes
    assert {"op": "remove", "path": "/calendar/events/event-09"} in changes
    assert len(changes) == 2
    assert Environment.diff(before, before) == []


def test_user_navigation_is_not_app_data() -> None:
    env = make_env(APPS, sample_world(), start_time=START)
    before = env.snapshot()
    ok(env.call("user", "open_app", {"app_name": "email"}))
    ok(env.call("user", "open_email_by_index", {"index": 0}))
    # opening an email marks it read, as a phone does; nothing of the navigation is app data
    assert Environment.diff(before, env.snapshot()) == [
        {"op": "replace", "path": "/email/emails/email-002/is_read", "value": True}
    ]


def test_noise_is_routed_like_real_events() -> None:
    env = make_env(APPS, sample_world(), start_time=START, seed=4, noise_rate_per_minute=2.0)
    emails_before = len(env.snapshot()["email"]["emails"])
    env.advance(timedelta(minutes=30))
    noise = [e for e in env.log if e.event_id and e.event_id.startswith("noise-")]
    assert 30 <= len(noise) <= 90
    assert all(e.actor == "env" and e.ok for e in noise)
    assert {e.tool for e in noise} == {"receive_email", "receive_message"}
    assert [e.time for e in noise] == sorted(e.time for e in noise)
    emails = sum(1 for e in noise if e.tool == "receive_email")
    assert len(env.snapshot()["email"]["emails"]) == emails_before + emails
    user_notes = env.user_view().notifications
    assistant_notes = env.assistant_observation().notifications
    assert len(user_notes) == len(assistant_notes) == len(noise)
    assert sum(len(n) for n in user_notes) < sum(len(n) for n in assistant_notes)


def test_same_seed_same_noise_different_seed_different_noise() -> None:
    def arrivals(seed: int) -> list[tuple[str, str]]:
        env = make_env(APPS, sample_world(), start_time=START, seed=seed, noise_rate_per_minute=3.0)
        env.advance(timedelta(minutes=20))
        return [(e.time.isoformat(), str(e.args)) for e in env.log]

    assert arrivals(1) == arrivals(1)
    assert arrivals(1) != arrivals(2)
