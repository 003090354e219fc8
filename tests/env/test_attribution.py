"""Attribution: which actor created or last changed each place of the app data."""

from __future__ import annotations

from pare.env import Environment
from pare.env.attribution import Attribution, changed_places, item_key, place_of, removed_places


def test_changed_places_name_items_by_identity() -> None:
    before = {"events": {"a": {"title": "x"}}, "saved": ["p1"], "cart": [{"item_id": "i1", "qty": 1}]}
    after = {
        "events": {"a": {"title": "y"}, "b": {"title": "z"}},
        "saved": ["p1", "p2"],
        "cart": [{"item_id": "i1", "qty": 2}],
    }
    assert sorted(changed_places(before, after)) == [
        (("cart", "i1", "qty"), False),
        (("events", "a", "title"), False),
        (("events", "b"), True),
        (("saved", "p2"), True),
    ]
    assert item_key({"qty": 1, "order_id": "o-1"}) == "o-1" and item_key(3) == "3"


def test_creator_and_last_changer() -> None:
    marks = Attribution()
    marks.record("assistant", 4, "calendar", {"events": {}}, {"events": {"e": {"title": "a"}}})
    marks.record("user", 9, "calendar", {"events": {"e": {"title": "a"}}}, {"events": {"e": {"title": "b"}}})
    mark = marks.mark(("calendar", "events", "e"))
    assert mark is not None and (mark.created_by, mark.changed_by, mark.created_at, mark.changed_at) == (
        "assistant",
        "user",
        4,
        9,
    )
    assert marks.credits(("calendar", "events", "e"), frozenset({"assistant"}))  # it made the event
    assert marks.credits(("calendar", "events"), frozenset({"user"}))  # the collection changed too
    assert not marks.credits(("calendar", "events", "other"), frozenset({"assistant", "user"}))


def test_place_of_turns_list_indexes_into_identities() -> None:
    state = {"shopping": {"orders": [{"order_id": "o-7", "total": 3}]}}
    assert place_of(state, "shopping.orders.0.total") == ("shopping", "orders", "o-7", "total")
    assert place_of(state, "shopping.orders.3") is None


def test_the_environment_marks_actor_writes_and_not_the_worlds() -> None:
    env = Environment(["calendar"])
    env.call(
        "env",
        "calendar__add_calendar_event",
        {"title": "Seeded", "start_datetime": "2025-01-07T10:00:00Z", "end_datetime": "2025-01-07T11:00:00Z"},
    )
    made = env.call(
        "assistant",
        "calendar__add_calendar_event",
        {"title": "Lunch", "start_datetime": "2025-01-07T12:00:00Z", "end_datetime": "2025-01-07T13:00:00Z"},
        mode="execute",
    )
    assert made.ok
    events = env.snapshot()["calendar"]["events"]
    by_title = {event["title"]: key for key, event in events.items()}
    assert env.attribution.mark(("calendar", "events", by_title["Seeded"])) is None
    mark = env.attribution.mark(("calendar", "events", by_title["Lunch"]))
    assert mark is not None and mark.created_by == "assistant" and mark.created_at == made.entry.index  # type: ignore[union-attr]
    failed = env.call("assistant", "calendar__delete_calendar_event", {"event_id": "nope"}, mode="execute")
    assert not failed.ok and env.attribution.mark(("calendar", "events", "nope")) is None


def test_who_last_set_each_field() -> None:
    marks = Attribution()
    made = {"events": {"e": {"title": "Dentist", "start": "10:00"}}}
    noted = {"events": {"e": {"title": "Dentist", "start": "10:00", "note": "letter"}}}
    marks.record("user", 3, "calendar", {"events": {}}, made)
    marks.record("assistant", 7, "calendar", made, noted)
    item, both = ("calendar", "events", "e"), frozenset({"assistant", "user"})
    assert marks.written_by(item, ["title", "start", "note"], frozenset({"assistant"})) == {"note"}
    assert marks.written_by(item, ["title", "start", "note"], frozenset({"user"})) == {"title", "start"}
    assert marks.written_by(item, ["title", "place"], both) == {"title", "place"}  # absent: the creator's
    assert marks.writer((*item, "title")) == "user" and marks.writer((*item, "note")) == "assistant"
    assert marks.writer(item) == "assistant"  # the item as a whole: its latest change
    assert marks.hands(item) == both
    assert marks.credits(item, frozenset({"assistant"}))  # the older reading, kept: created or last changed


def test_a_seeded_field_is_no_ones_and_a_recreated_item_forgets_the_old_ones_changes() -> None:
    marks = Attribution()
    seeded = {"events": {"e": {"title": "Dentist", "start": "10:00"}}}
    moved = {"events": {"e": {"title": "Dentist", "start": "11:00"}}}
    marks.record("assistant", 4, "calendar", seeded, moved)
    item = ("calendar", "events", "e")
    assert marks.written_by(item, ["title", "start"], frozenset({"assistant", "user"})) == {"start"}
    assert marks.writer((*item, "title")) is None
    marks.record("user", 6, "calendar", moved, {"events": {}})
    marks.record("user", 9, "calendar", {"events": {}}, moved)  # the same id again, by the user
    assert marks.written_by(item, ["start"], frozenset({"assistant"})) == frozenset()
    assert marks.writer((*item, "start")) == "user" and marks.hands(item) == {"user"}


def test_what_a_new_holder_holds_is_its_creators() -> None:
    marks = Attribution()
    chat = {"conversations": {"c": {"messages": [{"message_id": "m1", "content": "hi"}]}}}
    marks.record("assistant", 2, "messaging", {"conversations": {}}, chat)
    message = ("messaging", "conversations", "c", "messages", "m1")
    assert marks.writer((*message, "content")) == "assistant" and marks.hands(message) == {"assistant"}


def test_removals_are_kept_with_who_removed_them() -> None:
    before = {"events": {"a": {"attendees": ["Jo", "Sam"]}, "b": {}}, "saved": ["p1", "p2"]}
    after = {"events": {"a": {"attendees": ["Jo"]}}, "saved": ["p2"]}
    assert sorted(removed_places(before, after)) == [
        ("events", "a", "attendees", "Sam"),
        ("events", "b"),
        ("saved", "p1"),
    ]
    marks = Attribution()
    marks.record("assistant", 3, "calendar", before, after)
    assert marks.removals()[("calendar", "events", "b")] == ("assistant", 3)
    assert marks.mark(("calendar", "events", "b")) is None  # removing marks nothing the checks count
