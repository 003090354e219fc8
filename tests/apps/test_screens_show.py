"""What every screen displays when the user arrives on it (``Screen.display``), and what opening marks seen.

A phone shows a list when it opens and the item when one is opened; the environment shows ``display``'s
value on arrival and again when the app's data changes under the user's eyes. These tests call
``display`` directly (the environment's wiring is tested with the environment) and check that it is a
compact page, JSON-ready, consistent with the screen's own list action, and never changes data.
"""

from __future__ import annotations

import json
import random
from datetime import timedelta
from typing import Any

import pytest
from pydantic_core import to_jsonable_python

from pare.apps.registry import app_names, get_app_class
from pare.apps.sample_data import sample_world
from pare.apps.screens import Screen
from pare.apps.text import PAGE, preview, short_time
from pare.env import Environment
from pare.env.random_walk import RandomAssistant, RandomUser
from tests.conftest import START, make_env, ok, screen_of

APPS = app_names()


def shown(env: Environment) -> Any:
    """What the screen on view displays, as the user would be shown it (JSON values)."""
    screen = env.system.current_screen()
    assert screen is not None
    return to_jsonable_python(screen.display(env.apps[env.system.foreground or ""]))


def user(env: Environment, action: str, **args: Any) -> Any:
    return ok(env.call("user", action, args))


def agent(env: Environment, tool: str, **args: Any) -> Any:
    return ok(env.call("assistant", tool, args, mode="execute"))


def page_ids(items: list[dict[str, Any]], key: str) -> list[Any]:
    """The ``key`` of the items a list screen's first page shows."""
    return [item[key] for item in items][:PAGE]


@pytest.fixture
def env() -> Environment:
    return make_env(APPS, sample_world())


# -- every screen ------------------------------------------------------------------------------------


@pytest.mark.parametrize("name", APPS)
def test_every_screen_says_what_it_displays(name: str) -> None:
    for screen in get_app_class(name).screens:
        assert screen.display is not Screen.display, f"{name} > {screen.screen_name()} has no display"
        assert screen.display.__doc__, f"{name} > {screen.screen_name()}.display has no docstring"


def _largest_list(value: Any) -> int:
    if isinstance(value, list):
        return max([len(value), *(_largest_list(item) for item in value)])
    if isinstance(value, dict):
        return max([0, *(_largest_list(item) for item in value.values())])
    return 0


def test_displays_are_compact_json_and_change_nothing_along_a_random_walk() -> None:
    """Walk every screen of every app (the assistant changing data in between) and look at each."""
    env = make_env(APPS, sample_world(), seed=5)
    rng = random.Random(5)
    walker, assistant = RandomUser(rng), RandomAssistant(rng)
    looked: set[tuple[str, str]] = set()
    for step in range(12_000):  # ten apps: about a thousand steps each
        if step % 7 == 6:
            assistant.step(env)
        else:
            walker.step(env)
        screen = env.system.current_screen()
        if screen is None:
            continue
        app = env.apps[env.system.foreground or ""]
        before, writes = app.snapshot(), app.write_count
        value = to_jsonable_python(screen.display(app))
        assert app.snapshot() == before and app.write_count == writes, screen.label()
        text = json.dumps(value, ensure_ascii=False)
        assert value is not None, screen.label()
        assert len(text) < 8000, f"{screen.label()} displays {len(text)} characters"
        limit = 10 if screen.screen_name() == "Opened" else 7  # messages; else a page (or a cart, a product)
        assert _largest_list(value) <= limit or screen.screen_name() in ("Product", "Folders"), screen.label()
        looked.add((app.name, screen.screen_name()))
    every = {(name, s.screen_name()) for name in APPS for s in get_app_class(name).screens}
    assert looked == every


def test_text_helpers() -> None:
    assert preview("  Still on   for\n12:30? ") == "Still on for 12:30?"
    long = "word " * 40
    assert preview(long, 20) == "word word word word…"
    assert len(preview(long)) <= 61
    assert preview(None) == ""
    assert preview("x" * 100, 10) == "x" * 10 + "…"
    assert short_time(START) == "2025-03-03 09:00"
    assert short_time(None) is None


# -- email -------------------------------------------------------------------------------------------


def test_mailbox_shows_the_newest_emails_as_rows(env: Environment) -> None:
    user(env, "open_app", app_name="email")
    page = user(env, "list_emails")
    view = shown(env)
    assert (view["folder"], view["total"]) == ("INBOX", page["total"])
    everything = agent(env, "email__list_emails", limit=100)["emails"]
    assert view["unread"] == sum(not e["is_read"] for e in everything)
    assert page_ids(view["emails"], "email_id") == page_ids(page["emails"], "email_id")
    first, email = view["emails"][0], page["emails"][0]
    assert first == {
        "email_id": email["email_id"],
        "from": email["sender"],
        "subject": email["subject"],
        "time": short_time(env.apps["email"].state.emails[email["email_id"]].timestamp),
        "read": email["is_read"],
        "preview": preview(email["content"]),
        **({"attachments": len(email["attachments"])} if email["attachments"] else {}),
    }
    user(env, "switch_folder", folder="SENT")
    sent = shown(env)
    assert sent["folder"] == "SENT"
    assert all("to" in row and "from" not in row for row in sent["emails"])


def test_opening_an_email_marks_it_read_without_a_write(env: Environment) -> None:
    mail = env.apps["email"]
    user(env, "open_app", app_name="email")
    unread = [e for e in mail.in_folder("INBOX") if not e.is_read]
    assert len(unread) >= 2
    before_unread, writes = shown(env)["unread"], mail.write_count
    opened = user(env, "open_email", email_id=unread[0].email_id)
    assert opened["is_read"] is True  # the Detail screen shows it read, as it now is
    assert env.snapshot()["email"]["emails"][unread[0].email_id]["is_read"] is True
    assert shown(env)["is_read"] is True
    assert env.log[-1].kind == "ui" and mail.write_count == writes  # navigation, not the user's write
    user(env, "go_back")
    assert shown(env)["unread"] == before_unread - 1
    index = mail.in_folder("INBOX").index(unread[1])
    assert user(env, "open_email_by_index", index=index)["is_read"] is True
    assert mail.state.emails[unread[1].email_id].is_read
    assert mail.write_count == writes


def test_the_assistant_reading_an_email_leaves_it_unread(env: Environment) -> None:
    email = next(e for e in env.apps["email"].in_folder("INBOX") if not e.is_read)
    assert agent(env, "email__get_email_by_id", email_id=email.email_id)["is_read"] is False
    assert agent(env, "email__get_email_by_index", index=0)["email_id"]
    assert env.apps["email"].state.emails[email.email_id].is_read is False


def test_email_detail_and_compose_show_the_email_and_the_draft(env: Environment) -> None:
    user(env, "open_app", app_name="email")
    email = user(env, "open_email_by_index", index=0)
    assert shown(env) == email
    user(env, "start_compose_reply")
    draft = user(env, "set_body", body="Thanks!")
    assert shown(env) == draft and draft["body"] == "Thanks!"
    user(env, "discard")
    agent(env, "email__delete_email", email_id=email["email_id"])
    agent(env, "email__delete_email", email_id=email["email_id"])  # from TRASH: gone for good
    assert shown(env) == f"Email {email['email_id']} no longer exists."


def test_an_email_arriving_shows_in_the_open_mailbox(env: Environment) -> None:
    user(env, "open_app", app_name="email")
    total = shown(env)["total"]
    env.call("env", "email__receive_email", {"sender": "ana@x.example", "subject": "Hi", "content": "Lunch?"})
    view = shown(env)
    assert view["total"] == total + 1
    assert view["emails"][0] | {"time": None} == {
        "email_id": view["emails"][0]["email_id"],
        "from": "ana@x.example",
        "subject": "Hi",
        "time": None,
        "read": False,
        "preview": "Lunch?",
    }


# -- messaging ---------------------------------------------------------------------------------------


def test_conversation_list_shows_the_latest_conversations(env: Environment) -> None:
    user(env, "open_app", app_name="messaging")
    page = user(env, "list_recent_conversations")
    view = shown(env)
    assert view["total"] == page["total"]
    ids = [c["conversation_id"] for c in page["conversations"]]
    assert [row["conversation_id"] for row in view["conversations"]] == ids[:PAGE]
    row, listed = view["conversations"][0], page["conversations"][0]
    conversation = env.apps["messaging"].state.conversations[row["conversation_id"]]
    assert row["title"] == env.apps["messaging"].display_title(conversation)
    assert row["messages"] == listed["message_count"]
    last = listed["last_message"]
    who = "You" if last["from_current_user"] else last["sender_name"]
    assert row["last_message"] == f"{who}: {preview(last['content'])}"


def test_an_open_conversation_shows_its_latest_messages_and_what_arrives(env: Environment) -> None:
    user(env, "open_app", app_name="messaging")
    conversation_id = user(env, "list_recent_conversations")["conversations"][0]["conversation_id"]
    opened = user(env, "open_conversation", conversation_id=conversation_id)
    assert shown(env) == opened == user(env, "read_messages")
    long = "A long message that must arrive in full on the open screen, " * 5
    sender = next(p for p in opened["participants"] if not p["is_current_user"])["user_id"]
    arrived = {"sender": sender, "content": long, "conversation_id": conversation_id}
    ok(env.call("env", "messaging__receive_message", arrived))
    view = shown(env)
    assert view["messages"][0]["content"] == long.strip()
    assert len(view["messages"]) <= 10
    assert view["total_messages"] == opened["total_messages"] + 1


def test_a_long_conversation_says_how_to_see_its_older_messages() -> None:
    seed = {
        "messaging": {
            "users": {"user-me": "Me", "ann": "Ann"},
            "conversations": {
                "gift": {
                    "conversation_id": "gift",
                    "participant_ids": ["user-me", "ann"],
                    "messages": [
                        {
                            "message_id": f"m{n}",
                            "sender_id": "ann",
                            "content": f"Rule {n}" if n < 3 else f"Chat {n}",
                            "timestamp": f"2025-03-02T{8 + n:02d}:00:00Z",
                        }
                        for n in range(14)
                    ],
                }
            },
        }
    }
    env = make_env(["messaging"], seed)
    user(env, "open_app", app_name="messaging")
    opened = user(env, "open_conversation", conversation_id="gift")
    assert [m["content"] for m in opened["messages"]][-1] == "Chat 4"
    # the screen says its ten are not the whole conversation, and names its own action for the rest
    assert opened["showing"] == "1-10 of 14; read_messages(offset=10) shows the next"
    assert shown(env)["showing"] == opened["showing"]
    older = user(env, "read_messages", offset=10)
    assert [m["content"] for m in older["messages"]] == ["Chat 3", "Rule 2", "Rule 1", "Rule 0"]
    assert older["showing"] == "11-14 of 14 (the last)"


# -- calendar ----------------------------------------------------------------------------------------


def test_the_agenda_shows_the_actual_day_and_its_events(env: Environment) -> None:
    user(env, "open_app", app_name="calendar")
    screen = env.system.current_screen()
    assert screen is not None and screen.label().startswith("Agenda(day='2025-03-03'")
    listing = user(env, "list_events")
    view = shown(env)
    assert view["day"] == "Mon 2025-03-03"
    assert view["total"] == len(listing["events"])
    assert [row["event_id"] for row in view["events"]] == [e["event_id"] for e in listing["events"]][:PAGE]
    assert "tag" not in view
    # positions on screen are those open_event_by_index takes
    second = view["events"][1]["event_id"]
    assert user(env, "open_event_by_index", index=1)["event_id"] == second
    assert shown(env)["event_id"] == second
    user(env, "edit_event")
    draft = user(env, "set_location", location="Room 9")
    assert shown(env) == draft
    user(env, "discard")
    user(env, "go_back")
    tag = user(env, "get_all_tags")[0]
    user(env, "filter_by_tag", tag=tag)
    assert shown(env)["tag"] == tag


@pytest.mark.parametrize(
    ("action", "args"),
    [
        ("set_day", {"day": "2025-03-04"}),
        ("filter_by_tag", {"tag": "work"}),
        ("filter_by_attendee", {"attendee": "a"}),
    ],
)
def test_changing_the_agendas_day_or_filter_shows_the_compact_agenda(
    env: Environment, action: str, args: dict[str, Any]
) -> None:
    user(env, "open_app", app_name="calendar")
    changed = user(env, action, **args)
    # the same compact page the agenda shows on arrival (rows of id, title, times), not raw events
    assert changed == shown(env)
    assert changed["events"], "the sample day shows nothing: the test checks nothing"
    assert all("description" not in row and "attendees" not in row for row in changed["events"])


def test_an_event_removed_while_open_says_so(env: Environment) -> None:
    user(env, "open_app", app_name="calendar")
    event_id = user(env, "open_event_by_index", index=0)["event_id"]
    agent(env, "calendar__delete_calendar_event", event_id=event_id)
    assert shown(env) == f"Event {event_id} is no longer in the calendar."


def test_agenda_rows_give_hours_within_the_day_and_dates_across_days() -> None:
    seed = {
        "calendar": {
            "events": {
                "night": {
                    "event_id": "night",
                    "title": "Migration",
                    "start_datetime": "2025-03-02T22:00:00Z",
                    "end_datetime": "2025-03-03T02:00:00Z",
                },
                "lunch": {
                    "event_id": "lunch",
                    "title": "Lunch",
                    "start_datetime": "2025-03-03T12:00:00Z",
                    "end_datetime": "2025-03-03T13:00:00Z",
                    "location": "Noodle bar",
                    "tag": "social",
                },
            }
        }
    }
    env = make_env(["calendar"], seed)
    user(env, "open_app", app_name="calendar")
    assert shown(env)["events"] == [
        {"event_id": "night", "title": "Migration", "when": "Sun 2025-03-02 22:00 - Mon 2025-03-03 02:00"},
        {
            "event_id": "lunch",
            "title": "Lunch",
            "when": "12:00-13:00",
            "location": "Noodle bar",
            "tag": "social",
        },
    ]


# -- contacts ----------------------------------------------------------------------------------------


def test_contacts_show_a_page_of_names_and_the_contact(env: Environment) -> None:
    user(env, "open_app", app_name="contacts")
    page = user(env, "list_contacts")
    view = shown(env)
    assert view["total"] == page["total"]
    assert page_ids(view["contacts"], "contact_id") == page_ids(page["contacts"], "contact_id")
    first = page["contacts"][0]
    assert view["contacts"][0]["name"] == f"{first['first_name']} {first['last_name']}".strip()
    contact = user(env, "open_contact", contact_id="contact-me")
    assert shown(env) == contact
    user(env, "start_edit_contact")
    assert shown(env) == contact
    user(env, "update_contact", updates={"city": "Lisbon"})
    assert shown(env)["city"] == "Lisbon"
    assert [row.get("me") for row in view["contacts"]].count(True) <= 1


# -- notes -------------------------------------------------------------------------------------------


def test_notes_open_on_every_folder_with_the_folder_of_each_note(env: Environment) -> None:
    user(env, "open_app", app_name="notes")
    view = shown(env)
    notes = env.apps["notes"]
    assert view["folder"] == "all folders"
    assert view["total"] == len(notes.state.notes)
    assert view["folders"] == {f.name: f.note_count for f in notes.list_folders()}
    listed = user(env, "list_notes")["notes"]
    assert page_ids(view["notes"], "note_id") == page_ids(listed, "note_id")
    assert page_ids(view["notes"], "folder") == page_ids(listed, "folder")
    note = user(env, "open_note", note_id=listed[0]["note_id"])
    assert shown(env) == note
    user(env, "edit")
    draft = user(env, "set_title", title="Renamed")
    assert shown(env) == draft
    user(env, "discard")
    user(env, "go_back")
    user(env, "list_folders")
    folders = user(env, "list_folders")
    assert shown(env) == folders
    folder = next(name for name, count in view["folders"].items() if count)
    user(env, "open_folder", folder=folder)
    one = shown(env)
    assert one["folder"] == folder and {r["folder"] for r in one["notes"]} == {folder}
    agent(env, "notes__new_folder", name="Empty")
    user(env, "list_folders")
    user(env, "open_folder", folder="Empty")
    agent(env, "notes__delete_folder", name="Empty")
    assert shown(env)["gone"] == "This folder no longer exists."


# -- reminder ----------------------------------------------------------------------------------------


def test_reminders_show_the_soonest_with_what_is_due(env: Environment) -> None:
    user(env, "open_app", app_name="reminder")
    every = user(env, "list_all_reminders")
    due = user(env, "list_due_reminders")
    view = shown(env)
    assert (view["total"], view["due_now"]) == (len(every), len(due))
    assert [r["reminder_id"] for r in view["reminders"]] == [r["reminder_id"] for r in every][:PAGE]
    flagged = [r for r in view["reminders"] if r.get("due_now")]
    assert page_ids(flagged, "reminder_id") == page_ids(due, "reminder_id")
    reminder = user(env, "open_reminder", reminder_id=every[0]["reminder_id"])
    assert shown(env) == reminder
    user(env, "edit")
    draft = user(env, "set_title", title="Call the plumber")
    assert shown(env) == draft
    user(env, "cancel")
    agent(env, "reminder__delete_reminder", reminder_id=reminder["reminder_id"])
    assert shown(env) == f"Reminder {reminder['reminder_id']} no longer exists."


# -- shopping ----------------------------------------------------------------------------------------


def test_shop_screens_show_products_variants_cart_and_orders(env: Environment) -> None:
    user(env, "open_app", app_name="shopping")
    page = user(env, "list_products")
    home = shown(env)
    assert home["total_products"] == page["total"]
    assert [r["product_id"] for r in home["products"]] == [p["product_id"] for p in page["products"]][:PAGE]
    for row, summary in zip(home["products"], page["products"], strict=False):
        assert row["in_stock"] == summary["in_stock"]
        assert row.get("out_of_stock", []) == summary["out_of_stock"]
    cart = user(env, "view_cart")
    assert home["cart"] == {"items": cart["item_count"], "subtotal": cart["subtotal"]}
    assert shown(env) == cart
    user(env, "go_back")
    orders = user(env, "list_orders")
    assert home["latest_order"]["order_id"] == orders[0]["order_id"]
    view = shown(env)
    assert view["total"] == len(orders)
    assert [o["order_id"] for o in view["orders"]] == [o["order_id"] for o in orders][:PAGE]
    order = user(env, "view_order", order_id=orders[0]["order_id"])
    assert shown(env) == order
    user(env, "go_back")
    user(env, "go_back")
    product_id = page["products"][0]["product_id"]
    product = user(env, "view_product", product_id=product_id)
    assert shown(env) == product
    item_id = next(iter(product["variants"]))
    variant = user(env, "view_variant", item_id=item_id)
    assert shown(env) == variant


def test_a_price_range_and_the_sold_out_variants_on_the_front_page() -> None:
    seed = {
        "shopping": {
            "products": {
                "p": {
                    "product_id": "p",
                    "name": "Headphones",
                    "brand": "Sonique",
                    "variants": {
                        "b": {"item_id": "b", "name": "Black", "price": 199.0, "stock": 3},
                        "s": {"item_id": "s", "name": "Silver", "price": 209.5, "stock": 0},
                    },
                }
            }
        }
    }
    env = make_env(["shopping"], seed)
    user(env, "open_app", app_name="shopping")
    assert shown(env) == {
        "total_products": 1,
        "products": [
            {
                "product_id": "p",
                "name": "Headphones",
                "brand": "Sonique",
                "price": "$199.00-$209.50",
                "in_stock": [{"item_id": "b", "name": "Black", "price": 199.0}],
                "out_of_stock": [{"item_id": "s", "name": "Silver", "price": 209.5}],
            }
        ],
        "cart": {"items": 0, "subtotal": 0.0},
    }


# -- cab ---------------------------------------------------------------------------------------------


def test_cab_screens_show_the_ride_the_options_and_the_quote(env: Environment) -> None:
    cab = env.apps["cab"]
    user(env, "open_app", app_name="cab")
    home = shown(env)
    history = user(env, "get_ride_history")
    assert home["total_rides"] == history["total"]
    current = cab.current_ride()
    assert home["current_ride"] == (None if current is None else to_jsonable_python(current))
    assert all(r["ride_id"] != history["current_ride_id"] for r in home["recent_rides"])
    if current is not None:
        user(env, "open_current_ride")
        assert shown(env) == to_jsonable_python(current)
        user(env, "go_back")
    quotes = user(env, "list_rides", start_location="Home", end_location="Airport")
    view = shown(env)
    assert (view["from"], view["to"]) == ("Home", "Airport")
    assert [(o["service_type"], o["quotation_id"], o["price"]) for o in view["options"]] == [
        (q["service_type"], q["quotation_id"], q["price"]) for q in quotes
    ]
    assert all("max_passengers" in o for o in view["options"])
    quote = user(env, "get_quotation", service_type=quotes[0]["service_type"])
    assert shown(env) == quote


def test_cab_options_show_only_quotes_for_the_trip_and_time(env: Environment) -> None:
    user(env, "open_app", app_name="cab")
    later = (START + timedelta(hours=3)).strftime("%Y-%m-%d %H:%M")
    user(env, "list_rides", start_location="Home", end_location="Office")
    user(env, "go_back")
    timed = user(env, "list_rides", start_location="home", end_location="office", ride_time=later)
    assert [o["quotation_id"] for o in shown(env)["options"]] == [q["quotation_id"] for q in timed]


# -- apartment ---------------------------------------------------------------------------------------


def test_apartment_screens_show_listings_saved_ones_and_the_listing(env: Environment) -> None:
    user(env, "open_app", app_name="apartment")
    page = user(env, "list_apartments")
    home = shown(env)
    saved = env.apps["apartment"].state.saved
    assert (home["total"], home["saved"]) == (page["total"], len(saved))
    assert page_ids(home["listings"], "apartment_id") == page_ids(page["apartments"], "apartment_id")
    assert [r["saved"] for r in home["listings"]] == [
        a in saved for a in page_ids(page["apartments"], "apartment_id")
    ]
    user(env, "open_search")
    assert shown(env)["listings"] == page["total"]
    user(env, "go_back")
    user(env, "open_favorites")
    view = shown(env)
    assert [r["apartment_id"] for r in view["listings"]] == saved[:PAGE]
    apartment = user(env, "view_apartment", apartment_id=saved[0])
    assert shown(env) == apartment
    user(env, "unsave")
    assert shown(env)["saved"] is False
    ok(env.call("env", "apartment__delete_apartment", {"apartment_id": apartment["apartment_id"]}))
    assert shown(env) == f"Apartment {apartment['apartment_id']} is no longer listed."


# -- what models are told about searches --------------------------------------------------------------

PARTIAL_SEARCHES = {
    "email": ["search_emails"],
    "messaging": ["search", "search_conversations"],
    "calendar": ["search_events"],
    "contacts": ["search_contacts"],
    "notes": ["search_notes"],
    "shopping": ["search_product", "search_products"],
}


@pytest.mark.parametrize("name", sorted(PARTIAL_SEARCHES))
def test_searches_say_they_match_parts_of_words(name: str) -> None:
    cls = get_app_class(name)
    specs = [*cls.tools.values(), *(spec for screen in cls.screens for spec in screen.actions.values())]
    found = [spec for spec in specs if spec.name in PARTIAL_SEARCHES[name]]
    assert {spec.name for spec in found} == set(PARTIAL_SEARCHES[name])
    for spec in found:
        assert "parts of words" in spec.description and "Priyanka" in spec.description, spec.name


def test_the_apartment_location_filter_says_it_matches_parts_of_words() -> None:
    cls = get_app_class("apartment")
    for spec in (cls.tools["search_apartments"], cls.screen_class("Search").actions["search"]):
        described = " ".join(spec.parameters_schema["properties"]["location"]["description"].split())
        assert "parts of words" in described


def test_partial_matching_is_what_the_docstrings_say(env: Environment) -> None:
    agent(env, "contacts__add_new_contact", first_name="Priyanka", last_name="Rao")
    found = agent(env, "contacts__search_contacts", query="Priya")
    assert [c["first_name"] for c in found] == ["Priyanka"]
    assert screen_of(env) is None


# -- partial lists ----------------------------------------------------------------------------------

LIST_SCREENS = [
    # app, how to reach the list from the app's first screen, the rows' key, the total's key
    ("email", [], "emails", "total"),
    ("messaging", [], "conversations", "total"),
    ("contacts", [], "contacts", "total"),
    ("notes", [], "notes", "total"),
    ("reminder", [], "reminders", "total"),
    ("shopping", [], "products", "total_products"),
    ("shopping", [("list_orders", {})], "orders", "total"),
    ("cab", [], "recent_rides", "total_rides"),
    ("apartment", [], "listings", "total"),
]


@pytest.mark.parametrize(("app", "steps", "rows", "total"), LIST_SCREENS)
def test_a_list_screen_says_when_it_shows_part_and_how_to_see_the_rest(
    app: str, steps: list[tuple[str, dict[str, Any]]], rows: str, total: str
) -> None:
    env = make_env(APPS, sample_world())
    user(env, "open_app", app_name=app)
    for action, args in steps:
        user(env, action, **args)
    view = shown(env)
    # the cab's home shows the ride under way apart from the other rides
    count = len(view[rows]) + bool(view.get("current_ride"))
    if count >= view[total]:
        assert "showing" not in view  # a whole list needs no word about the rest
        return
    assert count == PAGE
    showing = view["showing"]
    assert showing.startswith(f"1-{PAGE} of {view[total]}; ")
    action = showing.split("; ", 1)[1].split("(", 1)[0]
    # the way to the rest is an action the user has on this very screen, and it pages as the screen does
    assert action in env.user_view().tool_names
    rest = user(env, action, **({"offset": PAGE} if "offset=" in showing else {}))
    assert rest


def test_the_sample_world_has_partial_lists_to_say_so_about() -> None:
    env = make_env(APPS, sample_world())
    partial = []
    for app, steps, _rows, _total in LIST_SCREENS:
        user(env, "open_app", app_name=app)
        for action, args in steps:
            user(env, action, **args)
        view = shown(env)
        if "showing" in view:
            partial.append(app)
        user(env, "go_home")
    assert partial, "no list screen of the sample world is longer than a page: the test above checks nothing"


@pytest.mark.parametrize(
    ("tool", "args", "rows"),
    [
        ("email__list_emails", {}, "emails"),
        ("messaging__list_recent_conversations", {}, "conversations"),
        ("contacts__get_contacts", {}, "contacts"),
        ("notes__list_notes", {}, "notes"),
        ("reminder__get_upcoming_reminders", {}, "reminders"),
        ("shopping__list_all_products", {}, "products"),
        ("cab__get_ride_history", {}, "rides"),
        ("apartment__list_all_apartments", {}, "apartments"),
    ],
)
def test_list_tools_page_as_the_screens_do_and_say_how_much(
    tool: str, args: dict[str, Any], rows: str
) -> None:
    env = make_env(APPS, sample_world())
    page = agent(env, tool, **args)
    assert len(page[rows]) == min(PAGE, page["total"])
    if page["total"] > PAGE:
        assert page["showing"] == f"1-{PAGE} of {page['total']}; offset={PAGE} shows the next"
    else:
        assert page["showing"] == f"all {page['total']}"
