from __future__ import annotations

import random
import re
from datetime import UTC, datetime, timedelta
from typing import Any

import pytest

from pare.apps.cab import CabApp
from pare.env import Environment
from pare.env.random_walk import RandomUser
from pare.errors import UserInputError
from tests.conftest import err, make_env, ok, screen_of

HOME = "Home, 24 Elm Street"
OFFICE = "Acme Analytics, 500 Market St"
AIRPORT = "SFO Airport Terminal 2"
DENTIST = "Bright Smile Dental, 12 Oak St"
LUIGIS = "Luigi's, 88 Columbus Ave"
GYM = "Studio 5, 410 Valencia St"
STATION = "Caltrain Station, 4th and King"


def ride(ride_id: str, start: str, end: str, service: str, pickup: str, **fields: Any) -> dict[str, Any]:
    """A seed ride; ``pickup`` is "MM-DD HH:MM" in 2025, UTC, and the ride was booked 10 minutes before."""
    pickup_time = datetime.fromisoformat(f"2025-{pickup}").replace(tzinfo=UTC)
    return {
        "ride_id": ride_id,
        "start_location": start,
        "end_location": end,
        "service_type": service,
        "pickup_time": pickup_time.isoformat(),
        "booked_at": (pickup_time - timedelta(minutes=10)).isoformat(),
        "distance_km": fields.pop("distance_km", 6.8),
        "duration_minutes": fields.pop("duration_minutes", 14),
        "price": fields.pop("price", 14.98),
        "status": fields.pop("status", "completed"),
        **fields,
    }


# The episode starts on Monday 2025-03-03 at 09:00 UTC (peak hours). A fortnight of past rides, with
# look-alike distractors: three commutes, two airport runs, rides cancelled either way.
# fmt: off
RIDES = [
    ride("ride-1", HOME, AIRPORT, "Van", "02-17 05:30", distance_km=21.4, duration_minutes=43, price=52.15,
         driver_name="Marco", vehicle="grey Ford Transit, plate 7XK 221"),
    ride("ride-2", AIRPORT, HOME, "Default", "02-21 22:10", distance_km=21.4, duration_minutes=43,
         price=37.29, driver_name="Aisha", vehicle="white Toyota Prius, plate 8ABC 123"),
    ride("ride-3", HOME, OFFICE, "Pool", "02-24 08:15", price=12.63, driver_name="Ken",
         vehicle="blue Honda Civic, plate 5TRW 880"),
    ride("ride-4", HOME, OFFICE, "Default", "02-25 08:20", status="cancelled_by_user"),
    ride("ride-5", HOME, OFFICE, "Default", "02-26 08:05", status="cancelled_by_driver",
         cancellation_reason="Flat tyre"),
    ride("ride-6", OFFICE, LUIGIS, "Premium", "02-27 19:00", distance_km=3.9, duration_minutes=8,
         price=17.01, driver_name="Sofia", vehicle="black Tesla Model S, plate 9LUX 004"),
    ride("ride-7", LUIGIS, HOME, "Default", "02-27 22:30", distance_km=8.2, duration_minutes=17,
         price=16.27, driver_name="Omar", vehicle="silver Hyundai Ioniq, plate 6HYB 552"),
    ride("ride-8", HOME, GYM, "Pool", "03-01 10:00", distance_km=4.5, duration_minutes=9, price=6.95,
         driver_name="Lin", vehicle="red Kia Niro, plate 4KIA 731"),
]
# fmt: on
SEED: dict[str, Any] = {
    "cab": {
        "rides": {r["ride_id"]: r for r in RIDES},
        "quotations": {
            "quote-1": {
                "quotation_id": "quote-1",
                "start_location": HOME,
                "end_location": STATION,
                "service_type": "Default",
                "pickup_time": "2025-03-01T17:00:00Z",
                "distance_km": 5.1,
                "duration_minutes": 11,
                "price": 15.7,
                "peak_pricing": True,
            }
        },
        "known_distances": {
            f"{HOME}|{AIRPORT}": 21.4,
            f"{OFFICE}|{HOME}": 6.8,
            f"{OFFICE}|{LUIGIS}": 3.9,
            f"{HOME}|{LUIGIS}": 8.2,
            f"{HOME}|{GYM}": 4.5,
            f"{HOME}|{DENTIST}": 2.3,
        },
    }
}
SERVICES = ["Default", "Premium", "Van", "Pool"]
# Home -> airport, 21.4 km, 43 minutes at 30 km/h. Off-peak: base + per_km * 21.4 + per_minute * 43.
AIRPORT_OFF_PEAK = {"Default": 37.29, "Premium": 66.01, "Van": 52.15, "Pool": 25.57}
AIRPORT_PEAK = {"Default": 46.61, "Premium": 82.51, "Van": 65.19, "Pool": 31.96}  # x1.25, rounded


@pytest.fixture
def env() -> Environment:
    env = make_env(["cab"], SEED)
    ok(env.call("user", "open_app", {"app_name": "cab"}))
    return env


def cab(env: Environment) -> dict[str, Any]:
    return env.snapshot()["cab"]


def stack(env: Environment) -> list[str]:
    return [s.screen_name() for s in env.system.stacks["cab"]]


def agent(env: Environment, tool: str, **args: object) -> Any:
    return ok(env.call("assistant", f"cab__{tool}", args, mode="execute"))


def world(env: Environment, tool: str, **args: object) -> Any:
    return ok(env.call("env", f"cab__{tool}", args))


def book_airport(env: Environment, **args: object) -> dict[str, Any]:
    return agent(env, "order_ride", start_location=HOME, end_location=AIRPORT, service_type="Default", **args)


def quiet(env: Environment) -> None:
    """Mark every notification so far as read by both recipients."""
    env.user_view()
    env.assistant_observation()


# -- seed data and pricing -------------------------------------------------------------------------


def test_default_service_types() -> None:
    env = make_env(["cab"])
    services = agent(env, "list_service_types")
    assert list(services) == SERVICES
    assert services["Van"]["max_passengers"] == 7
    assert services["Pool"]["max_passengers"] == 2
    assert all(s["description"] for s in services.values())


def test_seeded_service_types_replace_the_defaults() -> None:
    seed = {
        "cab": {
            "service_types": {"Taxi": {"base_fare": 4, "per_km": 2, "per_minute": 0, "max_passengers": 4}}
        }
    }
    env = make_env(["cab"], seed)
    assert list(agent(env, "list_service_types")) == ["Taxi"]
    quotes = agent(env, "list_rides", start_location="A", end_location="B", ride_time="2025-03-03 12:00")
    assert [q["service_type"] for q in quotes] == ["Taxi"]
    assert quotes[0]["price"] == round(4 + 2 * quotes[0]["distance_km"], 2)


@pytest.mark.parametrize(
    ("changes", "message"),
    [
        ({"rides": {"ride-9": RIDES[0]}}, "has ride_id 'ride-1'"),
        ({"quotations": {"q": SEED["cab"]["quotations"]["quote-1"]}}, "has quotation_id 'quote-1'"),
        ({"current_ride_id": "ride-99"}, "is not a ride"),
        ({"current_ride_id": "ride-2"}, "has already ended"),
        ({"rides": {"ride-1": {**RIDES[0], "status": "booked"}}}, "only one may be under way"),
        ({"known_distances": {"Home": 3.0}}, '"a|b"'),
        ({"known_distances": {"Home| ": 3.0}}, '"a|b"'),
        ({"known_distances": {"Home|HOME ": 3.0}}, "same place twice"),
        ({"known_distances": {"A|B": 0.0}}, "between 0.1 and 1000"),
        ({"known_distances": {"A|B": 3.0, "b|a": 4.0}}, "two distances"),
        ({"service_types": {}}, "at least one service type"),
        ({"rides": {"ride-1": {**RIDES[0], "status": "lost"}}}, "status"),
    ],
)
def test_seed_validation(changes: dict[str, Any], message: str) -> None:
    with pytest.raises(UserInputError, match="(?i)" + re.escape(message)):
        make_env(["cab"], {"cab": {**SEED["cab"], **changes}})


def test_a_seeded_current_ride_is_the_ride_under_way() -> None:
    current = ride(
        "ride-9", HOME, DENTIST, "Default", "03-03 09:05", status="driver_assigned", driver_name="Sam"
    )
    env = make_env(["cab"], {"cab": {"rides": {"ride-9": current}, "current_ride_id": "ride-9"}})
    assert agent(env, "get_current_ride_status")["driver_name"] == "Sam"


def test_distance_is_a_pure_symmetric_function_of_the_pair() -> None:
    app = CabApp()
    there = app.distance_km("Union Square", "Golden Gate Park")
    assert there == app.distance_km("  golden gate   PARK ", "UNION square")
    assert there == 32.8  # pinned: the hash must not change between versions
    for start, end in [("Home", "Work"), ("Gym", "Airport"), ("A", "B"), ("Pier 39", "Ferry Building")]:
        km = app.distance_km(start, end)
        assert 1.5 <= km <= 35.0
        assert km == round(km, 1)
        assert km == CabApp().distance_km(end, start)


def test_known_distances_override_the_hash(env: Environment) -> None:
    quote = agent(env, "get_quotation", start_location=OFFICE, end_location=HOME, service_type="Pool")
    assert (quote["distance_km"], quote["duration_minutes"]) == (6.8, 14)  # "Office|Home" given reversed
    quote = agent(
        env,
        "get_quotation",
        start_location=" home,  24 elm street",
        end_location=DENTIST,
        service_type="Pool",
    )
    assert (quote["distance_km"], quote["duration_minutes"]) == (2.3, 5)  # 4.6 minutes rounded up
    assert quote["start_location"] == "home, 24 elm street"  # spaces tidied, spelling kept


def test_prices_off_peak_and_at_peak(env: Environment) -> None:
    for ride_time, peak, expected in [
        ("2025-03-03 11:00", False, AIRPORT_OFF_PEAK),
        ("2025-03-03 15:59", False, AIRPORT_OFF_PEAK),
        ("2025-03-03 16:00", True, AIRPORT_PEAK),
        ("2025-03-03 18:59", True, AIRPORT_PEAK),
        ("2025-03-03 19:00", False, AIRPORT_OFF_PEAK),
        ("2025-03-04 06:59", False, AIRPORT_OFF_PEAK),
        ("2025-03-04 07:00", True, AIRPORT_PEAK),
    ]:
        quotes = agent(env, "list_rides", start_location=HOME, end_location=AIRPORT, ride_time=ride_time)
        assert {q["service_type"]: q["price"] for q in quotes} == expected, ride_time
        assert all(q["peak_pricing"] is peak for q in quotes), ride_time
        assert all((q["distance_km"], q["duration_minutes"]) == (21.4, 43) for q in quotes)


def test_same_inputs_give_the_same_numbers_in_any_environment() -> None:
    def quotes(env: Environment) -> list[dict[str, Any]]:
        return agent(env, "list_rides", start_location="Pier 39", end_location="Ferry Building")

    first, second = quotes(make_env(["cab"], SEED)), quotes(make_env(["cab"], SEED))
    assert first == second
    reverse = agent(make_env(["cab"]), "list_rides", start_location="Ferry Building", end_location="Pier 39")
    assert [q["price"] for q in reverse] == [q["price"] for q in first]


# -- Home ------------------------------------------------------------------------------------------


def test_opens_on_home(env: Environment) -> None:
    assert screen_of(env) == "Home"


def test_list_rides_shows_every_service_and_opens_options(env: Environment) -> None:
    quotes = ok(env.call("user", "list_rides", {"start_location": HOME, "end_location": AIRPORT}))
    assert screen_of(env) == "Options"
    assert [q["service_type"] for q in quotes] == SERVICES
    assert {q["service_type"]: q["price"] for q in quotes} == AIRPORT_PEAK  # it is 09:00
    assert all(q["pickup_time"] == "2025-03-03T09:00:00Z" for q in quotes)
    assert [q["quotation_id"] for q in quotes] == ["quote-2", "quote-3", "quote-4", "quote-5"]
    assert all(cab(env)["quotations"][q["quotation_id"]] == q for q in quotes)
    options = env.system.current_screen()
    assert options is not None
    assert options.model_dump() == {
        "start_location": HOME,
        "end_location": AIRPORT,
        "ride_time": None,
        "service_types": SERVICES,
    }
    assert env.log[-1].kind == "read"


def test_list_rides_for_later_keeps_the_time_on_options(env: Environment) -> None:
    quotes = ok(
        env.call(
            "user",
            "list_rides",
            {"start_location": f"  {HOME} ", "end_location": DENTIST, "ride_time": "2025-03-04 13:30"},
        )
    )
    assert all(q["pickup_time"] == "2025-03-04T13:30:00Z" and not q["peak_pricing"] for q in quotes)
    options = env.system.current_screen()
    assert options is not None
    assert options.model_dump(mode="json") == {
        "start_location": HOME,
        "end_location": DENTIST,
        "ride_time": "2025-03-04T13:30:00Z",
        "service_types": SERVICES,
    }


@pytest.mark.parametrize(
    ("args", "message"),
    [
        ({"start_location": HOME, "end_location": AIRPORT, "ride_time": "2025-03-03 08:59"}, "in the past"),
        ({"start_location": HOME, "end_location": " home, 24 ELM street "}, "the same place"),
        ({"start_location": "  ", "end_location": AIRPORT}, "must be given"),
        ({"start_location": HOME}, "end_location"),
        ({"start_location": HOME, "end_location": AIRPORT, "ride_time": "soon"}, "ride_time"),
    ],
)
def test_list_rides_errors_stay_home_and_change_nothing(env: Environment, args: dict, message: str) -> None:
    before = env.snapshot()
    err(env.call("user", "list_rides", args), message)
    assert env.snapshot() == before
    assert stack(env) == ["Home"]


def test_open_current_ride_without_one_is_an_error(env: Environment) -> None:
    err(env.call("user", "open_current_ride"), "no ride under way")
    assert screen_of(env) == "Home"


def test_open_current_ride(env: Environment) -> None:
    booked = book_airport(env)
    shown = ok(env.call("user", "open_current_ride"))
    assert shown == booked
    assert screen_of(env) == "Ride"
    assert ok(env.call("user", "view_ride"))["ride_id"] == booked["ride_id"]


def test_ride_history_pages_most_recent_first(env: Environment) -> None:
    page = ok(env.call("user", "get_ride_history", {"limit": 3}))
    assert [r["ride_id"] for r in page["rides"]] == ["ride-8", "ride-7", "ride-6"]
    assert (page["total"], page["offset"], page["current_ride_id"]) == (8, 0, None)
    page = ok(env.call("user", "get_ride_history", {"offset": 6}))
    assert [r["ride_id"] for r in page["rides"]] == ["ride-2", "ride-1"]
    assert screen_of(env) == "Home"
    assert env.log[-1].kind == "read"


# -- Options and Quote -----------------------------------------------------------------------------


def test_options_list_service_types(env: Environment) -> None:
    ok(env.call("user", "list_rides", {"start_location": HOME, "end_location": AIRPORT}))
    services = ok(env.call("user", "list_service_types"))
    assert list(services) == SERVICES
    assert services["Premium"]["per_km"] == 1.9
    assert screen_of(env) == "Options"


def test_options_get_quotation_opens_the_quote(env: Environment) -> None:
    ok(
        env.call(
            "user",
            "list_rides",
            {"start_location": HOME, "end_location": AIRPORT, "ride_time": "2025-03-03 14:00"},
        )
    )
    quote = ok(env.call("user", "get_quotation", {"service_type": "premium"}))
    assert screen_of(env) == "Quote"
    assert stack(env) == ["Home", "Options", "Quote"]
    assert quote["service_type"] == "Premium"
    assert quote["pickup_time"] == "2025-03-03T14:00:00Z"
    assert quote["price"] == AIRPORT_OFF_PEAK["Premium"]
    assert quote["quotation_id"] == "quote-3"  # the one list_rides already gave, not a copy
    assert ok(env.call("user", "show_quotation")) == quote


def test_options_unknown_service_type_is_an_error(env: Environment) -> None:
    ok(env.call("user", "list_rides", {"start_location": HOME, "end_location": AIRPORT}))
    before = env.snapshot()
    err(env.call("user", "get_quotation", {"service_type": "Helicopter"}), "default, premium, van, pool")
    assert env.snapshot() == before
    assert screen_of(env) == "Options"


def test_options_whose_time_has_passed_refuses_a_quote(env: Environment) -> None:
    ok(
        env.call(
            "user",
            "list_rides",
            {"start_location": HOME, "end_location": AIRPORT, "ride_time": "2025-03-03 09:30"},
        )
    )
    env.advance(timedelta(hours=1))
    err(env.call("user", "get_quotation", {"service_type": "Van"}), "in the past")
    assert screen_of(env) == "Options"


def test_quote_order_ride_books_the_quotation_as_quoted(env: Environment) -> None:
    ok(
        env.call(
            "user",
            "list_rides",
            {"start_location": HOME, "end_location": AIRPORT, "ride_time": "2025-03-03 17:45"},
        )
    )
    quote = ok(env.call("user", "get_quotation", {"service_type": "Van"}))
    env.advance(timedelta(minutes=30))  # the price is kept even though time moved on
    booked = ok(env.call("user", "order_ride"))
    assert screen_of(env) == "Ride"
    assert stack(env) == ["Home", "Options", "Ride"]
    assert env.log[-1].kind == "write"
    assert booked["ride_id"] == "ride-9"
    assert booked["pickup_time"] == "2025-03-03T17:45:00Z"
    assert booked["price"] == quote["price"] == AIRPORT_PEAK["Van"]
    assert (booked["distance_km"], booked["duration_minutes"]) == (21.4, 43)
    assert booked["status"] == "booked"
    assert booked["booked_at"] == "2025-03-03T09:30:00Z"
    assert (booked["driver_name"], booked["vehicle"], booked["cancellation_reason"]) == (None, None, None)
    assert cab(env)["rides"]["ride-9"] == booked
    assert cab(env)["current_ride_id"] == "ride-9"
    assert ok(env.call("user", "view_ride")) == booked


def test_quote_order_ride_with_a_ride_under_way_is_an_error(env: Environment) -> None:
    book_airport(env)
    ok(env.call("user", "list_rides", {"start_location": HOME, "end_location": DENTIST}))
    ok(env.call("user", "get_quotation", {"service_type": "Pool"}))
    before = env.snapshot()
    err(env.call("user", "order_ride"), "already have a ride under way", "ride-9")
    assert env.snapshot() == before
    assert screen_of(env) == "Quote"


def test_an_expired_quote_cannot_be_ordered(env: Environment) -> None:
    ok(env.call("user", "list_rides", {"start_location": HOME, "end_location": AIRPORT}))
    ok(env.call("user", "get_quotation", {"service_type": "Default"}))
    env.advance(timedelta(minutes=15))
    env.advance(timedelta(minutes=1))
    before = env.snapshot()
    err(env.call("user", "order_ride"), "has passed", "new quotation")
    assert env.snapshot() == before
    assert screen_of(env) == "Quote"


def test_a_quote_within_its_grace_period_can_be_ordered(env: Environment) -> None:
    ok(env.call("user", "list_rides", {"start_location": HOME, "end_location": AIRPORT}))
    ok(env.call("user", "get_quotation", {"service_type": "Default"}))
    env.advance(timedelta(minutes=15))
    assert ok(env.call("user", "order_ride"))["pickup_time"] == "2025-03-03T09:00:00Z"


# -- Ride ------------------------------------------------------------------------------------------


def test_cancel_ride_returns_home(env: Environment) -> None:
    ok(env.call("user", "list_rides", {"start_location": HOME, "end_location": OFFICE}))
    ok(env.call("user", "get_quotation", {"service_type": "Default"}))
    ride_id = ok(env.call("user", "order_ride"))["ride_id"]
    world(env, "update_ride_status", status="arriving", driver_name="Sam")
    result = ok(env.call("user", "cancel_ride"))
    assert ride_id in result
    assert stack(env) == ["Home"]
    assert env.log[-1].kind == "write"
    assert cab(env)["rides"][ride_id]["status"] == "cancelled_by_user"
    assert cab(env)["current_ride_id"] is None
    # a new ride can be booked now
    assert book_airport(env)["ride_id"] == "ride-10"


def test_cancel_ride_in_progress_is_refused(env: Environment) -> None:
    book_airport(env)
    ok(env.call("user", "open_current_ride"))
    world(env, "update_ride_status", status="in_progress", driver_name="Sam")
    before = env.snapshot()
    err(env.call("user", "cancel_ride"), "in_progress", "can no longer be cancelled")
    assert env.snapshot() == before
    assert screen_of(env) == "Ride"


def test_a_ride_that_ended_while_open_shows_its_end(env: Environment) -> None:
    ride_id = book_airport(env)["ride_id"]
    ok(env.call("user", "open_current_ride"))
    world(env, "driver_cancel_ride", reason="Car broke down")
    shown = ok(env.call("user", "view_ride"))
    assert (shown["status"], shown["cancellation_reason"]) == ("cancelled_by_driver", "Car broke down")
    # a ride booked meanwhile by the assistant is not cancelled from this old ride's screen
    book_airport(env)
    before = env.snapshot()
    err(env.call("user", "cancel_ride"), "cancelled_by_driver", "can no longer be cancelled")
    assert env.snapshot() == before
    assert cab(env)["rides"][ride_id]["status"] == "cancelled_by_driver"
    assert screen_of(env) == "Ride"


# -- agent API -------------------------------------------------------------------------------------


def test_agent_reads(env: Environment) -> None:
    assert list(agent(env, "list_service_types")) == SERVICES
    quotes = agent(env, "list_rides", start_location=HOME, end_location=AIRPORT)
    assert [q["service_type"] for q in quotes] == SERVICES
    quote = agent(env, "get_quotation", start_location=HOME, end_location=AIRPORT, service_type="Van")
    assert quote == quotes[2]
    assert agent(env, "get_ride", ride_id="ride-5")["cancellation_reason"] == "Flat tyre"
    page = agent(env, "get_ride_history", offset=1, limit=2)
    assert [r["ride_id"] for r in page["rides"]] == ["ride-7", "ride-6"]
    assert page["total"] == 8
    # no ride booked is a state the assistant reads, not an error
    assert agent(env, "get_current_ride_status").startswith("No ride is under way")


def test_quotations_are_kept_once(env: Environment) -> None:
    quote = agent(env, "get_quotation", start_location=HOME, end_location=LUIGIS, service_type="Default")
    before = env.snapshot()
    again = agent(env, "get_quotation", start_location=HOME, end_location=LUIGIS, service_type="default")
    assert again == quote
    assert env.snapshot() == before
    later = agent(
        env,
        "get_quotation",
        start_location=HOME,
        end_location=LUIGIS,
        service_type="Default",
        ride_time="2025-03-03 12:00",
    )
    assert later["quotation_id"] != quote["quotation_id"]
    assert later["price"] < quote["price"]  # off-peak


def test_agent_reads_are_available_in_observe_mode(env: Environment) -> None:
    result = env.call(
        "assistant", "cab__list_rides", {"start_location": HOME, "end_location": GYM}, mode="observe"
    )
    assert len(ok(result)) == 4
    args = {"start_location": HOME, "end_location": GYM, "service_type": "Pool"}
    err(env.call("assistant", "cab__order_ride", args, mode="observe"), "execute mode")
    assert cab(env)["current_ride_id"] is None


def test_agent_orders_follows_and_cancels_a_ride(env: Environment) -> None:
    booked = book_airport(env, ride_time="2025-03-03 16:30")
    assert booked["ride_id"] == "ride-9"
    assert booked["pickup_time"] == "2025-03-03T16:30:00Z"
    assert booked["price"] == AIRPORT_PEAK["Default"]
    assert booked["booked_at"] == "2025-03-03T09:00:00Z"
    # the ride keeps the quotation it was booked at, which is stored too
    quote = next(q for q in cab(env)["quotations"].values() if q["pickup_time"] == "2025-03-03T16:30:00Z")
    assert quote["price"] == booked["price"]
    assert agent(env, "get_current_ride_status") == booked
    assert agent(env, "get_ride_history", limit=1)["rides"] == [booked]
    assert agent(env, "get_ride_history")["current_ride_id"] == "ride-9"
    assert "ride-9" in agent(env, "user_cancel_ride")
    assert cab(env)["rides"]["ride-9"]["status"] == "cancelled_by_user"
    assert cab(env)["current_ride_id"] is None


def test_agent_orders_a_quotation(env: Environment) -> None:
    quotes = agent(
        env, "list_rides", start_location=OFFICE, end_location=LUIGIS, ride_time="2025-03-03 19:30"
    )
    booked = agent(env, "order_quotation", quotation_id=quotes[1]["quotation_id"])
    assert booked["service_type"] == "Premium"
    assert booked["pickup_time"] == "2025-03-03T19:30:00Z"
    assert (booked["distance_km"], booked["price"]) == (3.9, quotes[1]["price"])
    assert cab(env)["current_ride_id"] == booked["ride_id"]


@pytest.mark.parametrize(
    ("tool", "args", "message"),
    [
        ("get_ride", {"ride_id": "ghost"}, "no ride with id 'ghost'"),
        ("get_ride_history", {"limit": 0}, "limit"),
        ("get_ride_history", {"offset": -1}, "offset"),
        ("list_rides", {"start_location": HOME, "end_location": HOME.upper()}, "same place"),
        (
            "list_rides",
            {"start_location": HOME, "end_location": AIRPORT, "ride_time": "2025-03-02 12:00"},
            "past",
        ),
        ("get_quotation", {"start_location": HOME, "end_location": AIRPORT, "service_type": "Taxi"}, "taxi"),
        (
            "get_quotation",
            {"start_location": "", "end_location": AIRPORT, "service_type": "Van"},
            "must be given",
        ),
        (
            "get_quotation",
            {
                "start_location": HOME,
                "end_location": AIRPORT,
                "service_type": "Van",
                "ride_time": "2025-03-03 08:00",
            },
            "in the past",
        ),
        ("order_ride", {"start_location": HOME, "end_location": AIRPORT, "service_type": "Bike"}, "bike"),
        ("order_ride", {"start_location": HOME, "end_location": AIRPORT}, "service_type"),
        (
            "order_ride",
            {
                "start_location": HOME,
                "end_location": AIRPORT,
                "service_type": "Van",
                "ride_time": "2025-03-01 10:00",
            },
            "in the past",
        ),
        ("order_quotation", {"quotation_id": "ghost"}, "no quotation with id 'ghost'"),
        ("order_quotation", {"quotation_id": "quote-1"}, "has passed"),
        ("user_cancel_ride", {}, "no ride under way"),
    ],
)
def test_agent_api_errors_change_nothing(env: Environment, tool: str, args: dict, message: str) -> None:
    before = env.snapshot()
    err(env.call("assistant", f"cab__{tool}", args, mode="execute"), message)
    assert env.snapshot() == before


@pytest.mark.parametrize(
    ("tool", "args"),
    [
        ("order_ride", {"start_location": HOME, "end_location": DENTIST, "service_type": "Pool"}),
        ("order_ride", {"start_location": AIRPORT, "end_location": "Moon Base", "service_type": "Van"}),
        ("order_quotation", {"quotation_id": "quote-2"}),
    ],
)
def test_only_one_ride_at_a_time(env: Environment, tool: str, args: dict) -> None:
    agent(env, "list_rides", start_location=HOME, end_location=GYM)  # quote-2..quote-5
    book_airport(env)
    before = env.snapshot()
    err(env.call("assistant", f"cab__{tool}", args, mode="execute"), "already have a ride under way")
    assert env.snapshot() == before


def test_a_started_ride_cannot_be_cancelled_by_the_user(env: Environment) -> None:
    book_airport(env)
    world(env, "update_ride_status", status="in_progress")
    before = env.snapshot()
    err(env.call("assistant", "cab__user_cancel_ride", {}, mode="execute"), "can no longer be cancelled")
    assert env.snapshot() == before


def test_the_assistant_cannot_act_as_the_driver(env: Environment) -> None:
    book_airport(env)
    before = env.snapshot()
    for tool in ("driver_cancel_ride", "update_ride_status", "end_ride"):
        args = {"status": "arriving"} if tool == "update_ride_status" else {}
        err(env.call("assistant", f"cab__{tool}", args, mode="execute"))
    assert env.snapshot() == before


# -- the world -------------------------------------------------------------------------------------


def test_a_ride_from_driver_assigned_to_completed(env: Environment) -> None:
    ride_id = book_airport(env)["ride_id"]
    quiet(env)

    assigned = world(
        env,
        "update_ride_status",
        status="driver_assigned",
        driver_name="Sam",
        vehicle="white Toyota Prius, plate KX 4821",
    )
    assert (assigned["status"], assigned["driver_name"]) == ("driver_assigned", "Sam")
    assert cab(env)["rides"][ride_id] == assigned
    user = env.user_view().notifications
    assert len(user) == 1
    assert "Cab: Your driver Sam will pick you up — Home, 24 Elm Street → SFO Airport Terminal 2" in user[0]
    assert "ride_id" not in user[0]
    assistant = env.assistant_observation().notifications
    assert (
        "Vehicle: white Toyota Prius, plate KX 4821. Pickup 2025-03-03 09:00 at Home, 24 Elm Street."
        in (assistant[0])
    )
    assert "(ride_id=ride-9, status=driver_assigned)" in assistant[0]

    arriving = world(env, "update_ride_status", status="arriving")
    assert (arriving["driver_name"], arriving["vehicle"]) == ("Sam", "white Toyota Prius, plate KX 4821")
    assert "Your driver Sam is arriving" in env.user_view().notifications[0]
    notification = env.notifications.inboxes["assistant"].items[-1]
    assert (notification.kind, notification.data) == (
        "ride_status",
        {"ride_id": ride_id, "status": "arriving"},
    )

    world(env, "update_ride_status", status="in_progress")
    assert "Your ride to SFO Airport Terminal 2 has started" in env.user_view().notifications[0]
    assert "About 43 min to SFO Airport Terminal 2." in env.assistant_observation().notifications[-1]

    completed = world(env, "end_ride")
    assert completed["status"] == "completed"
    assert cab(env)["current_ride_id"] is None
    user = env.user_view().notifications
    assert "You have arrived at SFO Airport Terminal 2" in user[0]
    assert "$46.61" in user[0]
    notification = env.notifications.inboxes["assistant"].items[-1]
    assert (notification.kind, notification.data) == ("ride_completed", {"ride_id": ride_id, "price": 46.61})
    assert agent(env, "get_ride_history", limit=1)["rides"][0] == completed
    # no ride booked is a state the assistant reads, not an error
    assert agent(env, "get_current_ride_status").startswith("No ride is under way")


def test_status_steps_may_be_skipped_and_a_driver_may_change(env: Environment) -> None:
    book_airport(env)
    world(env, "update_ride_status", status="arriving")
    assert "Your driver is arriving" in env.user_view().notifications[-1]
    changed = world(
        env, "update_ride_status", status="in_progress", driver_name="Priya", vehicle="green Kia EV6"
    )
    assert (changed["driver_name"], changed["vehicle"]) == ("Priya", "green Kia EV6")


def test_end_ride_before_it_starts_completes_it(env: Environment) -> None:
    ride_id = book_airport(env)["ride_id"]
    assert world(env, "end_ride")["status"] == "completed"
    assert cab(env)["rides"][ride_id]["status"] == "completed"


def test_driver_cancels(env: Environment) -> None:
    ride_id = book_airport(env)["ride_id"]
    world(env, "update_ride_status", status="driver_assigned", driver_name="Sam")
    quiet(env)
    reason = "My car broke down on the highway and the tow truck will take at least an hour to arrive."
    cancelled = world(env, "driver_cancel_ride", reason=reason)
    assert (cancelled["status"], cancelled["cancellation_reason"]) == ("cancelled_by_driver", reason)
    assert cab(env)["current_ride_id"] is None
    user = env.user_view().notifications
    assert len(user) == 1
    assert "Cab: Your driver cancelled your ride — Home, 24 Elm Street → SFO Airport Terminal 2" in user[0]
    assert user[0].endswith("…")  # truncated like a phone notification
    assert "an hour to arrive" not in user[0]
    assistant = env.assistant_observation().notifications
    assert f"Reason: {reason[:-1]}. Book another ride in the Cab app." in assistant[0]
    assert "ride_id=ride-9" in assistant[0]
    assert env.notifications.inboxes["assistant"].items[-1].kind == "ride_cancelled"
    assert book_airport(env)["ride_id"] == "ride-10"
    assert cab(env)["rides"][ride_id]["status"] == "cancelled_by_driver"


def test_driver_cancels_without_a_reason(env: Environment) -> None:
    book_airport(env)
    assert world(env, "driver_cancel_ride")["cancellation_reason"] is None
    assert env.assistant_observation().notifications[-1].split("\n")[1] == "Book another ride in the Cab app."


@pytest.mark.parametrize(
    ("tool", "args"),
    [
        ("driver_cancel_ride", {"reason": "busy"}),
        ("update_ride_status", {"status": "arriving", "driver_name": "Sam"}),
        ("end_ride", {}),
    ],
)
def test_world_events_need_a_ride_under_way(env: Environment, tool: str, args: dict) -> None:
    quiet(env)
    before = env.snapshot()
    err(env.call("env", f"cab__{tool}", args), "no ride under way")
    assert env.snapshot() == before
    assert env.assistant_observation().notifications == []


@pytest.mark.parametrize(
    ("moves", "tool", "args", "message"),
    [
        ([], "update_ride_status", {"status": "booked"}, "status"),
        ([], "update_ride_status", {"status": "completed"}, "status"),
        (["arriving"], "update_ride_status", {"status": "arriving"}, "already arriving"),
        (["arriving"], "update_ride_status", {"status": "driver_assigned"}, "only move forward"),
        (["in_progress"], "update_ride_status", {"status": "arriving"}, "only move forward"),
        (["in_progress"], "driver_cancel_ride", {}, "in progress"),
    ],
)
def test_world_errors_change_nothing(
    env: Environment, moves: list[str], tool: str, args: dict, message: str
) -> None:
    book_airport(env)
    for status in moves:
        world(env, "update_ride_status", status=status, driver_name="Sam")
    quiet(env)
    before = env.snapshot()
    err(env.call("env", f"cab__{tool}", args), message)
    assert env.snapshot() == before
    assert env.assistant_observation().notifications == []


# -- a careless user -------------------------------------------------------------------------------


def test_a_random_user_walks_every_screen() -> None:
    env = make_env(["cab"], SEED)
    user = RandomUser(random.Random(0))
    for _ in range(1500):
        user.step(env)  # raise_internal_errors: a crash or an undeclared transition fails the test
    screens = {e.app_screen[1] for e in env.log if e.app_screen}
    assert screens == {"Home", "Options", "Quote", "Ride"}
    assert sum(e.ok for e in env.log) / len(env.log) > 0.5


@pytest.mark.parametrize(
    ("start", "end", "km"),
    [
        ("22 Fenwick Rd", "Eastbridge Airport North Terminal", 31.5),
        ("eastbridge airport (north terminal)", "22 FENWICK ROAD", 31.5),
        ("Home", "Harbour St station", 9.0),
        ("home", "Harbour Street Railway Station", 9.0),
    ],
)
def test_a_known_pair_is_found_however_its_places_are_written(start: str, end: str, km: float) -> None:
    app = CabApp()
    app.state.known_distances = {
        "22 Fenwick Road|Eastbridge Airport (North Terminal)": 31.5,
        "Home|Harbour Street": 9.0,
    }
    assert app.distance_km(start, end) == km


def test_another_place_is_not_taken_for_a_known_one() -> None:
    app = CabApp()
    app.state.known_distances = {"22 Fenwick Road|Eastbridge Airport (North Terminal)": 31.5}
    assert app.distance_km("22 Fenwick Road", "Eastbridge Airport South Terminal") != 31.5
    assert app.distance_km("24 Fenwick Road", "Eastbridge Airport North Terminal") != 31.5
