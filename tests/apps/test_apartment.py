from __future__ import annotations

import random
from typing import Any

import pytest

from pare.apps.text import PAGE
from pare.env import Environment
from pare.env.random_walk import RandomUser
from pare.errors import UserInputError
from tests.conftest import err, make_env, ok, screen_of


def listing(
    apartment_id: str,
    name: str,
    location: str,
    address: str,
    price: float,
    bedrooms: int,
    bathrooms: float,
    property_type: str,
    **fields: Any,
) -> dict[str, Any]:
    return {
        "apartment_id": apartment_id,
        "name": name,
        "location": location,
        "address": address,
        "price": price,
        "bedrooms": bedrooms,
        "bathrooms": bathrooms,
        "property_type": property_type,
        **fields,
    }


SF = "San Francisco, CA"
# Fourteen Bay Area listings. Distractors: "mission" is both the Mission District and Mission Bay, and
# "valencia" is an address in two neighbourhoods; two listings rent for the same price; one listing has
# no square footage, pet policy or lease term.
# fmt: off
LISTINGS = [
    listing("apt-101", "Sunny 2BR near Dolores Park", "Mission District, San Francisco",
            f"3421 20th St, {SF} 94110", 3200, 2, 1, "Apartment", square_footage=950,
            furnished_status="Unfurnished", floor_level="Upper", pet_policy="Cats allowed",
            lease_term="1 year", amenities=["In-unit laundry", "Hardwood floors", "Bike storage"],
            available_from="2025-04-01T00:00:00Z",
            description="Top-floor flat with bay windows, two blocks from Dolores Park."),
    listing("apt-102", "Mission loft with roof deck", "Mission District, San Francisco",
            f"2250 Harrison St, {SF} 94110", 2950, 1, 1, "Condo", square_footage=780,
            furnished_status="Furnished", floor_level="Upper", pet_policy="Pets allowed",
            lease_term="6 months", amenities=["Roof deck", "Gym", "In-unit laundry"]),
    listing("apt-103", "Cozy studio on Valencia", "Mission District, San Francisco",
            f"801 Valencia St, {SF} 94110", 2100, 0, 1, "Studio", square_footage=420,
            furnished_status="Semi-furnished", floor_level="Ground", pet_policy="No pets",
            lease_term="Month-to-month", amenities=["Laundry room"]),
    listing("apt-104", "Noe Valley family house", "Noe Valley, San Francisco",
            f"412 Elizabeth St, {SF} 94114", 5800, 3, 2.5, "House", square_footage=1850,
            furnished_status="Unfurnished", floor_level="Ground", pet_policy="Dogs allowed",
            lease_term="Long term", amenities=["Garden", "Parking", "Dishwasher"]),
    listing("apt-105", "Bright 2BR in Noe Valley", "Noe Valley, San Francisco",
            f"1280 Church St, {SF} 94114", 3650, 2, 2, "Apartment", square_footage=1100,
            furnished_status="Unfurnished", floor_level="Upper", pet_policy="Pets allowed",
            lease_term="1 year", amenities=["Dishwasher", "Parking", "Balcony"],
            available_from="2025-03-15T00:00:00Z"),
    listing("apt-106", "SoMa high-rise penthouse", "SoMa, San Francisco", f"338 Spear St, {SF} 94105",
            6900, 2, 2, "Condo", square_footage=1400, furnished_status="Furnished", floor_level="Penthouse",
            pet_policy="Pets allowed", lease_term="1 year", amenities=["Gym", "Pool", "Doorman", "Parking"]),
    listing("apt-107", "SoMa 1BR with gym", "SoMa, San Francisco", f"1000 Folsom St, {SF} 94103",
            2950, 1, 1, "Apartment", square_footage=690, furnished_status="Unfurnished", floor_level="Upper",
            pet_policy="Cats allowed", lease_term="1 year", amenities=["Gym", "Laundry room"]),
    listing("apt-108", "Garden-level 1BR in the Sunset", "Outer Sunset, San Francisco",
            f"1730 Irving St, {SF} 94122", 2300, 1, 1, "Apartment", square_footage=650,
            furnished_status="Unfurnished", floor_level="Basement", pet_policy="No pets", lease_term="1 year",
            amenities=["Garden", "Laundry room"]),
    listing("apt-109", "Sunset townhouse near the beach", "Outer Sunset, San Francisco",
            f"4415 Judah St, {SF} 94122", 4200, 3, 2, "Townhouse", square_footage=1500,
            furnished_status="Semi-furnished", floor_level="Ground", pet_policy="Dogs allowed",
            lease_term="Long term", amenities=["Parking", "Garden", "Fireplace"]),
    listing("apt-110", "Oakland Lake Merritt 2BR", "Lake Merritt, Oakland",
            "155 Grand Ave, Oakland, CA 94612", 2600, 2, 1, "Apartment", square_footage=900,
            furnished_status="Unfurnished", floor_level="Upper", pet_policy="Pets allowed",
            lease_term="1 year", amenities=["Gym", "Parking"]),
    listing("apt-111", "Rockridge craftsman", "Rockridge, Oakland", "5523 College Ave, Oakland, CA 94618",
            3900, 3, 1.5, "House", square_footage=1400, furnished_status="Unfurnished", floor_level="Ground",
            pet_policy="Pets allowed", lease_term="Long term", amenities=["Garden", "Dishwasher", "Parking"]),
    listing("apt-112", "Furnished Berkeley studio", "Downtown Berkeley",
            "2020 Kittredge St, Berkeley, CA 94704", 1850, 0, 1, "Studio", square_footage=380,
            furnished_status="Furnished", floor_level="Upper", pet_policy="No pets", lease_term="6 months",
            amenities=["Bike storage"]),
    listing("apt-113", "Mission Bay condo", "Mission Bay, San Francisco", f"255 Berry St, {SF} 94158",
            4100, 2, 2, "Condo", amenities=["Gym", "Pool", "Concierge"]),
    listing("apt-114", "Valencia Street 2BR", "Bernal Heights, San Francisco",
            f"3500 Valencia St, {SF} 94110", 3400, 2, 1, "Apartment", square_footage=1000,
            furnished_status="Unfurnished", floor_level="Upper", pet_policy="Cats allowed",
            lease_term="1 year", amenities=["In-unit laundry", "Parking"]),
]
# fmt: on
SAVED = ["apt-105", "apt-101", "apt-110"]
SEED = {"apartment": {"apartments": {a["apartment_id"]: a for a in LISTINGS}, "saved": SAVED}}
BY_NAME = [
    "apt-105",
    "apt-103",
    "apt-112",
    "apt-108",
    "apt-113",
    "apt-102",
    "apt-104",
    "apt-110",
    "apt-111",
    "apt-107",
    "apt-106",
    "apt-101",
    "apt-109",
    "apt-114",
]
BY_PRICE = [
    "apt-112",
    "apt-103",
    "apt-108",
    "apt-110",
    "apt-102",
    "apt-107",
    "apt-101",
    "apt-114",
    "apt-105",
    "apt-111",
    "apt-113",
    "apt-109",
    "apt-104",
    "apt-106",
]


@pytest.fixture
def env() -> Environment:
    env = make_env(["apartment"], SEED)
    ok(env.call("user", "open_app", {"app_name": "apartment"}))
    return env


def state(env: Environment) -> dict:
    return env.snapshot()["apartment"]


def ids(listings: list[dict]) -> list[str]:
    return [a["apartment_id"] for a in listings]


def stack(env: Environment) -> list[str]:
    return [s.screen_name() for s in env.system.stacks["apartment"]]


def agent(env: Environment, tool: str, **args: object) -> Any:
    return ok(env.call("assistant", f"apartment__{tool}", args, mode="execute"))


def world(env: Environment, tool: str, **args: object) -> Any:
    return ok(env.call("env", f"apartment__{tool}", args))


def search(env: Environment, **filters: object) -> list[str]:
    """The ids the Search screen shows for ``filters`` (every match, on one page)."""
    page = ok(env.call("user", "search", {"limit": 100, **filters}))
    assert page["total"] == len(page["apartments"])
    return ids(page["apartments"])


def clear_notifications(env: Environment) -> None:
    env.user_view()
    env.assistant_observation()


# -- seed data -----------------------------------------------------------------------------------------


def test_seed_accepts_any_case_and_stores_the_canonical_values() -> None:
    weird = listing(
        "x",
        "Loft",
        "SoMa",
        "1 Main St",
        2000,
        1,
        1,
        "CONDO",
        furnished_status="semi furnished",
        floor_level="ground floor",
        pet_policy="no PETS",
        lease_term="12 months",
    )
    env = make_env(["apartment"], {"apartment": {"apartments": {"x": weird}}})
    stored = state(env)["apartments"]["x"]
    assert (stored["property_type"], stored["furnished_status"], stored["floor_level"]) == (
        "Condo",
        "Semi-furnished",
        "Ground",
    )
    assert (stored["pet_policy"], stored["lease_term"]) == ("No pets", "1 year")
    assert stored["amenities"] == [] and stored["square_footage"] is None and stored["available_from"] is None


@pytest.mark.parametrize(
    ("data", "message"),
    [
        ({"apartments": {"y": LISTINGS[0]}}, "has apartment_id 'apt-101'"),
        ({"apartments": {"apt-101": LISTINGS[0]}, "saved": ["apt-999"]}, "unknown apartment(s) apt-999"),
        ({"apartments": {"apt-101": LISTINGS[0]}, "saved": ["apt-101", "apt-101"]}, "more than once"),
        ({"apartments": {"z": listing("z", "Z", "SoMa", "1 Main St", -5, 1, 1, "Condo")}}, "price"),
        ({"apartments": {"z": listing("z", " ", "SoMa", "1 Main St", 5, 1, 1, "Condo")}}, "empty name"),
        ({"apartments": {"z": listing("z", "Z", "SoMa", "1 Main St", 5, 1, 1, "Castle")}}, "property_type"),
    ],
)
def test_seed_is_validated(data: dict, message: str) -> None:
    with pytest.raises(UserInputError) as error:
        make_env(["apartment"], {"apartment": data})
    assert message in str(error.value)


# -- Home ----------------------------------------------------------------------------------------------


def test_opens_on_home(env: Environment) -> None:
    assert screen_of(env) == "Home"


def test_list_apartments_pages_sorted_by_name(env: Environment) -> None:
    page = ok(env.call("user", "list_apartments"))
    # a page as long as the home screen's, and it says how to see the rest
    assert ids(page["apartments"]) == BY_NAME[:PAGE]
    assert (page["total"], page["offset"]) == (14, 0)
    assert page["showing"] == "1-5 of 14; offset=5 shows the next"
    page = ok(env.call("user", "list_apartments", {"offset": 10, "limit": 10}))
    assert ids(page["apartments"]) == BY_NAME[10:]
    assert ok(env.call("user", "list_apartments", {"offset": 20}))["apartments"] == []
    assert screen_of(env) == "Home"
    assert env.log[-1].kind == "read"


@pytest.mark.parametrize("args", [{"limit": 0}, {"limit": 101}, {"offset": -1}])
def test_list_apartments_rejects_bad_pages(env: Environment, args: dict) -> None:
    err(env.call("user", "list_apartments", args), "offset must be >= 0 and limit between 1 and 100")
    assert screen_of(env) == "Home"


def test_view_apartment_from_home_opens_detail(env: Environment) -> None:
    shown = ok(env.call("user", "view_apartment", {"apartment_id": "apt-101"}))
    assert shown["name"] == "Sunny 2BR near Dolores Park"
    assert shown["saved"] is True
    assert shown["available_from"].startswith("2025-04-01T00:00:00")
    assert screen_of(env) == "Detail"
    assert stack(env) == ["Home", "Detail"]
    assert env.user_view().screen == "Detail(apartment_id='apt-101')"


def test_view_unknown_apartment_is_an_error_and_stays(env: Environment) -> None:
    err(env.call("user", "view_apartment", {"apartment_id": "apt-999"}), "no apartment with id 'apt-999'")
    assert screen_of(env) == "Home"


def test_open_search_goes_to_search(env: Environment) -> None:
    shown = ok(env.call("user", "open_search"))
    assert "14 listings" in shown
    assert screen_of(env) == "Search"
    assert stack(env) == ["Home", "Search"]


def test_open_favorites_shows_the_saved_apartments(env: Environment) -> None:
    shown = ok(env.call("user", "open_favorites"))
    assert ids(shown) == SAVED
    assert screen_of(env) == "Saved"
    assert stack(env) == ["Home", "Saved"]


# -- Search --------------------------------------------------------------------------------------------


@pytest.fixture
def on_search(env: Environment) -> Environment:
    ok(env.call("user", "open_search"))
    return env


def test_search_without_filters_lists_everything_by_price(on_search: Environment) -> None:
    page = ok(on_search.call("user", "search"))
    assert ids(page["apartments"]) == BY_PRICE[:PAGE]  # apt-102 and apt-107 share a price: by id
    assert page["total"] == 14
    page = ok(on_search.call("user", "search", {"offset": 12, "limit": 5}))
    assert ids(page["apartments"]) == BY_PRICE[12:]
    assert (page["total"], page["offset"]) == (14, 12)
    assert screen_of(on_search) == "Search"
    assert on_search.log[-1].kind == "read"


def test_search_by_location_matches_neighbourhood_city_or_address(on_search: Environment) -> None:
    # the Mission District and Mission Bay
    assert search(on_search, location="MISSION") == ["apt-103", "apt-102", "apt-101", "apt-113"]
    assert search(on_search, location="mission district") == ["apt-103", "apt-102", "apt-101"]
    assert search(on_search, location="oakland") == ["apt-110", "apt-111"]
    # an address in the Mission and one in Bernal Heights
    assert search(on_search, location="valencia st") == ["apt-103", "apt-114"]
    assert search(on_search, location="94122") == ["apt-108", "apt-109"]
    assert search(on_search, location="Paris") == []


def test_search_by_price_bedrooms_bathrooms_and_size(on_search: Environment) -> None:
    assert search(on_search, min_price=2950, max_price=3200) == ["apt-102", "apt-107", "apt-101"]
    assert search(on_search, max_price=2100) == ["apt-112", "apt-103"]
    assert search(on_search, min_bedrooms=3) == ["apt-111", "apt-109", "apt-104"]
    assert search(on_search, min_bedrooms=0, max_bedrooms=0) == ["apt-112", "apt-103"]
    assert search(on_search, min_bathrooms=2.5) == ["apt-104"]
    assert search(on_search, min_bedrooms=2, max_price=3500, min_bathrooms=1) == [
        "apt-110",
        "apt-101",
        "apt-114",
    ]
    # Mission Bay states no size, so any size filter leaves it out
    assert search(on_search, min_square_footage=1400) == ["apt-111", "apt-109", "apt-104", "apt-106"]
    assert search(on_search, min_square_footage=1000, max_square_footage=1100) == ["apt-114", "apt-105"]
    assert "apt-113" not in search(on_search, max_square_footage=5000)


def test_search_by_kind_of_listing(on_search: Environment) -> None:
    assert search(on_search, property_type="condo") == ["apt-102", "apt-113", "apt-106"]
    assert search(on_search, property_type="Studio", furnished_status="FURNISHED") == ["apt-112"]
    assert search(on_search, furnished_status="semi-furnished") == ["apt-103", "apt-109"]
    assert search(on_search, pet_policy="Dogs allowed") == ["apt-109", "apt-104"]
    assert search(on_search, pet_policy="no pets") == ["apt-112", "apt-103", "apt-108"]
    assert search(on_search, lease_term="month to month") == ["apt-103"]
    assert search(on_search, lease_term="6 Months", location="mission") == ["apt-102"]
    assert search(on_search, floor_level="basement") == ["apt-108"]
    assert search(on_search, floor_level="Penthouse") == ["apt-106"]


def test_search_by_amenities_needs_every_one(on_search: Environment) -> None:
    assert search(on_search, amenities=["gym"]) == ["apt-110", "apt-102", "apt-107", "apt-113", "apt-106"]
    assert search(on_search, amenities=["Gym", "PARKING"]) == ["apt-110", "apt-106"]
    assert search(on_search, amenities=["in-unit laundry", " "]) == ["apt-102", "apt-101", "apt-114"]
    assert search(on_search, amenities=["Laundry"]) == []  # names are matched whole


@pytest.mark.parametrize(
    ("args", "message"),
    [
        ({"min_price": 4000, "max_price": 3000}, "min_price (4000.0) is above max_price (3000.0)"),
        ({"min_bedrooms": 3, "max_bedrooms": 1}, "min_bedrooms (3) is above max_bedrooms (1)"),
        ({"min_square_footage": 900, "max_square_footage": 500}, "min_square_footage"),
        ({"max_price": -1}, "max_price cannot be negative"),
        ({"min_bathrooms": -1}, "min_bathrooms cannot be negative"),
        ({"location": "  "}, "location is empty"),
        ({"amenities": ["", " "]}, "amenities lists no amenity name"),
        ({"property_type": "Castle"}, "property_type"),
        ({"limit": 0}, "limit between 1 and 100"),
    ],
)
def test_search_errors_stay_on_search(on_search: Environment, args: dict, message: str) -> None:
    before = on_search.snapshot()
    err(on_search.call("user", "search", args), message)
    assert on_search.snapshot() == before
    assert screen_of(on_search) == "Search"


def test_view_apartment_from_search_opens_detail(on_search: Environment) -> None:
    shown = ok(on_search.call("user", "view_apartment", {"apartment_id": "apt-113"}))
    assert shown["saved"] is False
    assert shown["square_footage"] is None and shown["pet_policy"] is None
    assert stack(on_search) == ["Home", "Search", "Detail"]
    ok(on_search.call("user", "go_back"))
    assert screen_of(on_search) == "Search"
    err(on_search.call("user", "view_apartment", {"apartment_id": "nope"}), "no apartment with id 'nope'")
    assert screen_of(on_search) == "Search"


# -- Saved ---------------------------------------------------------------------------------------------


@pytest.fixture
def on_saved(env: Environment) -> Environment:
    ok(env.call("user", "open_favorites"))
    return env


def test_list_saved_shows_them_in_the_order_saved(on_saved: Environment) -> None:
    shown = ok(on_saved.call("user", "list_saved"))
    assert ids(shown) == SAVED
    assert shown[0]["price"] == 3650
    assert screen_of(on_saved) == "Saved"
    assert on_saved.log[-1].kind == "read"


def test_view_apartment_from_saved_opens_detail_of_any_listing(on_saved: Environment) -> None:
    assert ok(on_saved.call("user", "view_apartment", {"apartment_id": "apt-110"}))["saved"] is True
    assert stack(on_saved) == ["Home", "Saved", "Detail"]
    ok(on_saved.call("user", "go_back"))
    # not a saved one: it opens all the same
    assert ok(on_saved.call("user", "view_apartment", {"apartment_id": "apt-106"}))["saved"] is False
    assert screen_of(on_saved) == "Detail"
    ok(on_saved.call("user", "go_back"))
    err(on_saved.call("user", "view_apartment", {"apartment_id": "apt-0"}), "no apartment with id 'apt-0'")
    assert screen_of(on_saved) == "Saved"


def test_unsaving_from_detail_shows_in_the_saved_list(on_saved: Environment) -> None:
    ok(on_saved.call("user", "view_apartment", {"apartment_id": "apt-101"}))
    ok(on_saved.call("user", "unsave"))
    ok(on_saved.call("user", "go_back"))
    assert ids(ok(on_saved.call("user", "list_saved"))) == ["apt-105", "apt-110"]


# -- Detail --------------------------------------------------------------------------------------------


def open_detail(env: Environment, apartment_id: str) -> None:
    ok(env.call("user", "view_apartment", {"apartment_id": apartment_id}))


def test_view_details_shows_the_listing_as_it_is_now(env: Environment) -> None:
    open_detail(env, "apt-102")
    shown = ok(env.call("user", "view_details"))
    assert shown["apartment_id"] == "apt-102"
    assert shown["amenities"] == ["Roof deck", "Gym", "In-unit laundry"]
    assert shown["saved"] is False
    world(env, "update_apartment", apartment_id="apt-102", updates={"price": 2800})
    assert ok(env.call("user", "view_details"))["price"] == 2800
    assert screen_of(env) == "Detail"
    assert env.log[-1].kind == "read"


def test_save_adds_to_the_end_of_the_saved_list_and_stays(env: Environment) -> None:
    open_detail(env, "apt-102")
    assert "Saved apartment apt-102" in ok(env.call("user", "save"))
    assert state(env)["saved"] == [*SAVED, "apt-102"]
    assert screen_of(env) == "Detail"
    assert env.log[-1].kind == "write"
    assert ok(env.call("user", "view_details"))["saved"] is True


def test_unsave_removes_from_the_saved_list_and_stays(env: Environment) -> None:
    open_detail(env, "apt-101")
    assert "Removed apartment apt-101" in ok(env.call("user", "unsave"))
    assert state(env)["saved"] == ["apt-105", "apt-110"]
    assert state(env)["apartments"]["apt-101"]["name"] == "Sunny 2BR near Dolores Park"  # the listing stays
    assert screen_of(env) == "Detail"
    assert env.log[-1].kind == "write"
    assert ok(env.call("user", "view_details"))["saved"] is False


@pytest.mark.parametrize(
    ("apartment_id", "tool", "message"),
    [("apt-105", "save", "already saved"), ("apt-102", "unsave", "not in the saved apartments")],
)
def test_detail_errors_change_nothing(env: Environment, apartment_id: str, tool: str, message: str) -> None:
    open_detail(env, apartment_id)
    before = env.snapshot()
    err(env.call("user", tool), message)
    assert env.snapshot() == before
    assert screen_of(env) == "Detail"


def test_detail_of_a_listing_taken_down_meanwhile(env: Environment) -> None:
    open_detail(env, "apt-102")
    world(env, "delete_apartment", apartment_id="apt-102")
    before = env.snapshot()
    for tool in ("view_details", "save", "unsave"):
        err(env.call("user", tool), "no apartment with id 'apt-102'")
    assert env.snapshot() == before
    assert screen_of(env) == "Detail"


# -- the assistant's API -----------------------------------------------------------------------------


def test_agent_read_api(env: Environment) -> None:
    page = agent(env, "list_all_apartments", limit=3)
    assert ids(page["apartments"]) == BY_NAME[:3]
    assert (page["total"], page["offset"]) == (14, 0)
    assert ids(agent(env, "list_all_apartments", offset=13)["apartments"]) == ["apt-114"]
    details = agent(env, "get_apartment_details", apartment_id="apt-104")
    assert details["bathrooms"] == 2.5 and details["property_type"] == "House"
    assert details["lease_term"] == "Long term" and details["saved"] is False
    assert agent(env, "get_apartment_details", apartment_id="apt-105")["saved"] is True
    found = agent(env, "search_apartments", location="San Francisco", max_price=3000, limit=2)
    assert ids(found["apartments"]) == ["apt-103", "apt-108"]
    assert found["total"] == 4
    found = agent(env, "search_apartments", pet_policy="Pets allowed", amenities=["parking"], min_bedrooms=2)
    assert ids(found["apartments"]) == ["apt-110", "apt-105", "apt-111", "apt-106"]
    assert ids(agent(env, "list_saved_apartments")) == SAVED


def test_agent_write_api(env: Environment) -> None:
    assert agent(env, "save_apartment", apartment_id="apt-112") == (
        "Saved apartment apt-112 (Furnished Berkeley studio)."
    )
    assert agent(env, "remove_saved_apartment", apartment_id="apt-105") == (
        "Removed apartment apt-105 (Bright 2BR in Noe Valley) from the saved apartments."
    )
    assert state(env)["saved"] == ["apt-101", "apt-110", "apt-112"]
    assert ids(agent(env, "list_saved_apartments")) == ["apt-101", "apt-110", "apt-112"]
    assert len(state(env)["apartments"]) == 14


def test_write_tools_are_not_offered_in_observe_mode(env: Environment) -> None:
    before = env.snapshot()
    err(env.call("assistant", "apartment__save_apartment", {"apartment_id": "apt-112"}), "execute mode")
    assert env.snapshot() == before
    observe = {tool.name for tool in env.assistant_tools("observe")}
    assert {"apartment__search_apartments", "apartment__list_saved_apartments"} <= observe
    assert "apartment__save_apartment" not in observe
    execute = {tool.name for tool in env.assistant_tools("execute")}
    assert "apartment__remove_saved_apartment" in execute
    assert not {"apartment__add_new_apartment", "apartment__update_apartment"} & execute


@pytest.mark.parametrize(
    ("tool", "args", "message"),
    [
        ("list_all_apartments", {"limit": 0}, "limit between 1 and 100"),
        ("list_all_apartments", {"offset": -2}, "offset must be >= 0"),
        ("get_apartment_details", {"apartment_id": "ghost"}, "no apartment with id 'ghost'"),
        ("search_apartments", {"min_price": 3000, "max_price": 2000}, "is above max_price"),
        ("search_apartments", {"min_bedrooms": -1}, "min_bedrooms cannot be negative"),
        ("search_apartments", {"location": ""}, "location is empty"),
        ("search_apartments", {"lease_term": "forever"}, "lease_term"),
        ("search_apartments", {"pet_policy": "Birds allowed"}, "pet_policy"),
        ("save_apartment", {"apartment_id": "apt-101"}, "already saved"),
        ("save_apartment", {"apartment_id": "ghost"}, "no apartment with id 'ghost'"),
        ("remove_saved_apartment", {"apartment_id": "apt-106"}, "not in the saved apartments"),
        ("remove_saved_apartment", {"apartment_id": "ghost"}, "no apartment with id 'ghost'"),
        ("save_apartment", {}, "missing required argument 'apartment_id'"),
    ],
)
def test_agent_api_errors_change_nothing(env: Environment, tool: str, args: dict, message: str) -> None:
    before = env.snapshot()
    err(env.call("assistant", f"apartment__{tool}", args, mode="execute"), message)
    assert env.snapshot() == before


# -- the world -----------------------------------------------------------------------------------------


def test_add_new_apartment_appears_silently(env: Environment) -> None:
    clear_notifications(env)
    new_id = world(
        env,
        "add_new_apartment",
        name="  Hayes Valley 1BR  ",
        location="Hayes Valley, San Francisco",
        address=f"500 Hayes St, {SF} 94102",
        price=2750,
        bedrooms=1,
        bathrooms=1,
        furnished_status="unfurnished",
        floor_level="upper floors",
        pet_policy="cats ALLOWED",
        lease_term="1 Year",
        amenities=["Gym", " gym ", "", "Bike storage"],
        available_from="2025-04-15",
        description="  Quiet unit facing the courtyard.  ",
    )
    assert new_id == "apt-115"  # numbering continues after the seeded ids
    stored = state(env)["apartments"][new_id]
    assert stored["name"] == "Hayes Valley 1BR"
    assert stored["property_type"] == "Apartment"
    assert (stored["floor_level"], stored["pet_policy"], stored["lease_term"]) == (
        "Upper",
        "Cats allowed",
        "1 year",
    )
    assert stored["amenities"] == ["Gym", "Bike storage"]
    assert stored["available_from"].startswith("2025-04-15T00:00:00")
    assert stored["description"] == "Quiet unit facing the courtyard."
    assert state(env)["saved"] == SAVED
    assert env.user_view().notifications == []
    assert env.assistant_observation().notifications == []
    ok(env.call("user", "open_search"))
    assert search(env, location="hayes") == [new_id]


def test_add_new_apartment_with_a_chosen_id(env: Environment) -> None:
    args = {"location": "Marina, San Francisco", "address": "1 Chestnut St", "bedrooms": 1, "bathrooms": 1}
    assert world(
        env, "add_new_apartment", name="Marina flat", price=3100, apartment_id="apt-marina", **args
    ) == ("apt-marina")
    assert state(env)["apartments"]["apt-marina"]["price"] == 3100
    assert world(
        env, "add_new_apartment", name="Marina studio", price=2000, property_type="studio", **args
    ) == ("apt-115")
    assert state(env)["apartments"]["apt-115"]["property_type"] == "Studio"


@pytest.mark.parametrize(
    ("args", "message"),
    [
        ({"apartment_id": "apt-101"}, "already exists"),
        ({"apartment_id": "  "}, "cannot be empty"),
        ({"name": " "}, "needs a name"),
        ({"address": ""}, "needs a address"),
        ({"price": -100}, "price cannot be negative"),
        ({"bedrooms": -1}, "bedrooms cannot be negative"),
        ({"square_footage": 0}, "square_footage must be positive"),
        ({"floor_level": "Attic"}, "floor_level"),
        ({"price": "cheap"}, "price"),
    ],
)
def test_add_new_apartment_errors_change_nothing(env: Environment, args: dict, message: str) -> None:
    before = env.snapshot()
    call = {
        "name": "Marina flat",
        "location": "Marina",
        "address": "1 Chestnut St",
        "price": 3100,
        "bedrooms": 1,
        "bathrooms": 1,
        **args,
    }
    err(env.call("env", "apartment__add_new_apartment", call), message)
    assert env.snapshot() == before


def test_price_drop_on_a_saved_listing_notifies_both(env: Environment) -> None:
    clear_notifications(env)
    updated = world(env, "update_apartment", apartment_id="apt-105", updates={"price": 3400})
    assert updated["price"] == 3400
    assert state(env)["apartments"]["apt-105"]["price"] == 3400
    assert state(env)["apartments"]["apt-105"]["bedrooms"] == 2  # the rest is kept

    user_notes = env.user_view().notifications
    assert len(user_notes) == 1
    assert "Price drop on a saved apartment — Bright 2BR in Noe Valley" in user_notes[0]
    assert "Now $3,400 a month, down from $3,650." in user_notes[0]
    assert "94114" not in user_notes[0] and "apt-105" not in user_notes[0]  # a phone shows the first words
    assert user_notes[0].endswith("…")

    assistant_notes = env.assistant_observation().notifications
    assert len(assistant_notes) == 1
    assert f"Now $3,400 a month, down from $3,650. Address: 1280 Church St, {SF} 94114." in assistant_notes[0]
    assert "apartment_id=apt-105" in assistant_notes[0] and "old_price=3650" in assistant_notes[0]


def test_price_drop_with_other_changes_names_them(env: Environment) -> None:
    clear_notifications(env)
    world(env, "update_apartment", apartment_id="apt-110", updates={"price": 2450, "lease_term": "6 months"})
    (note,) = env.assistant_observation().notifications
    assert "down from $2,600. Also changed: lease term. Address: 155 Grand Ave" in note


def test_other_changes_to_a_saved_listing_notify_listing_updated(env: Environment) -> None:
    clear_notifications(env)
    updates = {"price": 3350, "pet_policy": "no pets", "amenities": ["In-unit laundry", "Bike storage"]}
    world(env, "update_apartment", apartment_id="apt-101", updates=updates)
    stored = state(env)["apartments"]["apt-101"]
    assert (stored["price"], stored["pet_policy"]) == (3350, "No pets")
    assert stored["amenities"] == ["In-unit laundry", "Bike storage"]

    (user_note,) = env.user_view().notifications
    assert "A saved apartment was updated" in user_note and "Sunny 2BR near Dolores Park" in user_note
    assert "Changed: rent: $3,200 -> $3,350; pet policy: Cats allowed -> No pets; …" in user_note
    assert "Hardwood" not in user_note and "20th St" not in user_note
    (note,) = env.assistant_observation().notifications
    assert "rent: $3,200 -> $3,350" in note
    assert "pet policy: Cats allowed -> No pets" in note
    assert (
        "amenities: In-unit laundry, Hardwood floors, Bike storage -> In-unit laundry, Bike storage" in note
    )
    assert "apartment_id=apt-101" in note


def test_removing_optional_fields_of_a_saved_listing(env: Environment) -> None:
    clear_notifications(env)
    world(
        env,
        "update_apartment",
        apartment_id="apt-105",
        updates={"available_from": None, "description": "Newly renovated kitchen."},
    )
    stored = state(env)["apartments"]["apt-105"]
    assert stored["available_from"] is None and stored["description"] == "Newly renovated kitchen."
    (note,) = env.assistant_observation().notifications
    assert "available from: 2025-03-15 -> none; new description" in note


def test_changes_to_unsaved_listings_and_no_op_updates_are_silent(env: Environment) -> None:
    clear_notifications(env)
    world(env, "update_apartment", apartment_id="apt-106", updates={"price": 6500})
    assert state(env)["apartments"]["apt-106"]["price"] == 6500
    world(
        env, "update_apartment", apartment_id="apt-105", updates={"price": 3650, "property_type": "apartment"}
    )
    assert env.user_view().notifications == []
    assert env.assistant_observation().notifications == []


@pytest.mark.parametrize(
    ("args", "message"),
    [
        ({"apartment_id": "ghost", "updates": {"price": 1}}, "no apartment with id 'ghost'"),
        ({"apartment_id": "apt-105", "updates": {}}, "no field to change"),
        ({"apartment_id": "apt-105", "updates": {"price": None}}, "price cannot be removed"),
        ({"apartment_id": "apt-105", "updates": {"name": "  "}}, "name cannot be empty"),
        ({"apartment_id": "apt-105", "updates": {"price": -3}}, "updates.price"),
        ({"apartment_id": "apt-105", "updates": {"square_footage": 0}}, "updates.square_footage"),
        ({"apartment_id": "apt-105", "updates": {"furnished_status": "Half"}}, "updates.furnished_status"),
        ({"apartment_id": "apt-105", "updates": {"views": "ocean"}}, "updates.views"),
    ],
)
def test_update_errors_change_nothing_and_notify_nobody(env: Environment, args: dict, message: str) -> None:
    clear_notifications(env)
    before = env.snapshot()
    err(env.call("env", "apartment__update_apartment", args), message)
    assert env.snapshot() == before
    assert env.user_view().notifications == []
    assert env.assistant_observation().notifications == []


def test_deleting_a_saved_listing_removes_it_and_notifies(env: Environment) -> None:
    clear_notifications(env)
    assert world(env, "delete_apartment", apartment_id="apt-101") == (
        "Deleted apartment apt-101 (Sunny 2BR near Dolores Park)."
    )
    assert "apt-101" not in state(env)["apartments"]
    assert state(env)["saved"] == ["apt-105", "apt-110"]

    (user_note,) = env.user_view().notifications
    assert "A saved apartment is no longer listed" in user_note and "Sunny 2BR near Dolores Park" in user_note
    assert "Taken off the market and removed from your saved apartments." in user_note
    assert "20th St" not in user_note
    (note,) = env.assistant_observation().notifications
    assert f"It was $3,200 a month at 3421 20th St, {SF} 94110." in note and "apartment_id=apt-101" in note
    assert ids(agent(env, "list_saved_apartments")) == ["apt-105", "apt-110"]


def test_deleting_an_unsaved_listing_is_silent(env: Environment) -> None:
    clear_notifications(env)
    world(env, "delete_apartment", apartment_id="apt-106")
    assert "apt-106" not in state(env)["apartments"]
    assert state(env)["saved"] == SAVED
    assert env.user_view().notifications == []
    assert env.assistant_observation().notifications == []
    # a new listing never reuses the id of a deleted one
    args = {"location": "SoMa", "address": "2 Main St", "price": 3000, "bedrooms": 1, "bathrooms": 1}
    assert world(env, "add_new_apartment", name="New", **args) == "apt-115"
    world(env, "delete_apartment", apartment_id="apt-115")
    assert world(env, "add_new_apartment", name="Newer", **args) == "apt-116"


def test_delete_unknown_listing_changes_nothing(env: Environment) -> None:
    before = env.snapshot()
    err(env.call("env", "apartment__delete_apartment", {"apartment_id": "ghost"}), "ghost")
    assert env.snapshot() == before


def test_world_methods_are_not_for_the_assistant_or_user(env: Environment) -> None:
    err(
        env.call("assistant", "apartment__delete_apartment", {"apartment_id": "apt-101"}, mode="execute"),
        "not available",
    )
    err(env.call("user", "delete_apartment", {"apartment_id": "apt-101"}), "unknown action")
    assert "apt-101" in state(env)["apartments"]


# -- a careless user -----------------------------------------------------------------------------------


def test_a_random_user_walks_every_screen_without_breaking_anything() -> None:
    env = make_env(["apartment"], SEED)
    user = RandomUser(random.Random(0))
    for _ in range(1500):
        user.step(env)  # raise_internal_errors: a crash or an undeclared transition fails the test
    tried = {(e.app_screen[1], e.tool) for e in env.log if e.app_screen}
    for screen, action in [
        ("Home", "list_apartments"),
        ("Search", "search"),
        ("Saved", "list_saved"),
        ("Detail", "save"),
        ("Detail", "unsave"),
    ]:
        assert (screen, action) in tried
