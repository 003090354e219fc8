from __future__ import annotations

import copy
import random
from datetime import timedelta
from typing import Any

import pytest

from pare.bench import EpisodeSettings
from pare.env import Environment
from pare.env.random_walk import RandomUser
from pare.errors import UserInputError
from tests.conftest import err, make_env, ok, screen_of


def product(
    product_id: str, name: str, brand: str, category: str, description: str, *variants: tuple
) -> dict:
    """A seed product; each variant is ``(item_id, name, price, stock, options)``."""
    return {
        "product_id": product_id,
        "name": name,
        "brand": brand,
        "category": category,
        "description": description,
        "variants": {
            item_id: {"item_id": item_id, "name": vname, "price": price, "stock": stock, "options": options}
            for item_id, vname, price, stock, options in variants
        },
    }


def order(order_id: str, placed: str, status: str, items: list[tuple], **amounts: Any) -> dict:
    """A seed order; each item is ``(item_id, product_name, variant_name, quantity, unit_price)``."""
    subtotal = round(sum(q * p for _, _, _, q, p in items), 2)
    discount = amounts.get("discount", 0)
    return {
        "order_id": order_id,
        "items": [
            {"item_id": i, "product_name": pn, "variant_name": vn, "quantity": q, "unit_price": p}
            for i, pn, vn, q, p in items
        ],
        "subtotal": subtotal,
        "discount_code": amounts.get("discount_code"),
        "discount": discount,
        "total": round(subtotal - discount, 2),
        "status": status,
        "placed_at": f"2025-{placed}:00Z",
    }


def color_size(color: str, size: str) -> dict:
    return {"color": color, "size": size}


# The episode starts on Monday 2025-03-03 at 09:00 UTC. A small store with look-alike products (three
# Stride running shoes, two Northline items in blue), a cart of two lines, discount codes in every state
# (usable, minimum not reached, expired, inactive, expiring today) and orders in every status.
# fmt: off
PRODUCTS = [
    product("prod-trail", "Trail Runner 3", "Stride", "Shoes", "Light trail running shoe, grippy sole.",
            ("trail-blue-42", "Blue / 42", 89.99, 5, color_size("Blue", "42")),
            ("trail-blue-43", "Blue / 43", 89.99, 0, color_size("Blue", "43")),
            ("trail-black-42", "Black / 42", 94.99, 2, color_size("Black", "42"))),
    product("prod-trail-gtx", "Trail Runner 3 GTX", "Stride", "Shoes", "Waterproof Trail Runner 3.",
            ("gtx-grey-42", "Grey / 42", 129.99, 3, color_size("Grey", "42"))),
    product("prod-road", "Road Racer", "Stride", "Shoes", "Cushioned running shoe for the road.",
            ("road-white-42", "White / 42", 110.00, 4, color_size("White", "42"))),
    product("prod-hoodie", "Everyday Hoodie", "Northline", "Clothing", "Cotton fleece hoodie.",
            ("hoodie-blue-m", "Blue / M", 49.50, 10, color_size("Blue", "M")),
            ("hoodie-blue-l", "Blue / L", 49.50, 1, color_size("Blue", "L")),
            ("hoodie-grey-m", "Grey / M", 45.00, 0, color_size("Grey", "M"))),
    product("prod-socks", "Running Socks 3-pack", "Stride", "Clothing", "Merino socks for running.",
            ("socks-m", "M", 14.99, 30, {"size": "M"}),
            ("socks-l", "L", 14.99, 25, {"size": "L"})),
    product("prod-kettle", "Electric Kettle 1.7L", "Hearth", "Kitchen", "Steel kettle, auto shut-off.",
            ("kettle-steel", "Steel", 39.99, 7, {"finish": "Steel"})),
    product("prod-mug", "Ceramic Mug", "Hearth", "Kitchen", "350 ml mug, dishwasher safe.",
            ("mug-white", "White", 8.50, 40, {"color": "White"}),
            ("mug-blue", "Blue", 8.50, 12, {"color": "Blue"})),
    product("prod-headphones", "Noise Cancelling Headphones", "Sonique", "Electronics",
            "Over-ear wireless headphones with 30 hours of battery.",
            ("hp-black", "Black", 199.00, 6, {"color": "Black"}),
            ("hp-silver", "Silver", 199.00, 0, {"color": "Silver"})),
    product("prod-charger", "USB-C Charger 65W", "Sonique", "Electronics", "Charges laptops and phones.",
            ("charger-white", "White", 34.99, 15, {"color": "White"})),
    product("prod-yoga", "Yoga Mat", "Northline", "Fitness", "Non-slip 6 mm mat.",
            ("yoga-purple", "Purple", 29.99, 8, {"color": "Purple"})),
    product("prod-bottle", "Insulated Water Bottle", "Hydra", "Fitness", "Keeps drinks cold for 24 hours.",
            ("bottle-500", "500 ml", 24.00, 20, {"volume": "500 ml"}),
            ("bottle-750", "750 ml", 28.00, 0, {"volume": "750 ml"})),
    product("prod-daypack", "Daypack 20L", "Northline", "Bags", "Light hiking backpack with a rain cover.",
            ("pack-green", "Green", 64.00, 3, {"color": "Green"})),
]
CODES = [
    {"code": "SPRING15", "description": "Spring sale", "percent_off": 15, "min_subtotal": 50,
     "expires_at": "2025-03-31T23:59:00Z"},
    {"code": "WELCOME10", "description": "Welcome gift", "amount_off": 10},
    {"code": "BIGSPEND50", "description": "50 off big baskets", "amount_off": 50, "min_subtotal": 250},
    {"code": "WINTER20", "description": "Winter sale", "percent_off": 20,
     "expires_at": "2025-02-28T23:59:00Z"},
    {"code": "STAFF30", "description": "Staff discount", "percent_off": 30, "active": False},
    {"code": "Flash5", "description": "Flash sale", "percent_off": 5, "expires_at": "2025-03-03T12:00:00Z"},
]
ORDERS = [
    order("order-5", "01-20T10:00", "cancelled",
          [("kettle-steel", "Electric Kettle 1.7L", "Steel", 1, 39.99)]),
    order("order-1", "02-10T18:30", "delivered", [("mug-blue", "Ceramic Mug", "Blue", 2, 8.50)]),
    order("order-2", "02-25T08:15", "shipped", [("yoga-purple", "Yoga Mat", "Purple", 1, 29.99)],
          discount=10, discount_code="WELCOME10"),
    order("order-3", "03-01T12:00", "processing", [("charger-white", "USB-C Charger 65W", "White", 1, 34.99),
                                                   ("socks-m", "Running Socks 3-pack", "M", 1, 14.99)]),
    order("order-4", "03-02T20:45", "placed", [("hoodie-grey-m", "Everyday Hoodie", "Grey / M", 1, 45.00)]),
]
# fmt: on
SEED = {
    "shopping": {
        "products": {p["product_id"]: p for p in PRODUCTS},
        "cart": {"trail-blue-42": 1, "hoodie-blue-m": 2},
        "discount_codes": {c["code"]: c for c in CODES},
        "orders": {o["order_id"]: o for o in ORDERS},
    }
}
CART_SUBTOTAL = 188.99  # 89.99 + 2 x 49.50


@pytest.fixture
def env() -> Environment:
    env = make_env(["shopping"], SEED)
    ok(env.call("user", "open_app", {"app_name": "shopping"}))
    return env


def data(env: Environment) -> dict:
    return env.snapshot()["shopping"]


def stock(env: Environment, product_id: str, item_id: str) -> int:
    return data(env)["products"][product_id]["variants"][item_id]["stock"]


def stack(env: Environment) -> list[str]:
    return [s.screen_name() for s in env.system.stacks["shopping"]]


def agent(env: Environment, tool: str, **args: object) -> Any:
    return ok(env.call("assistant", f"shopping__{tool}", args, mode="execute"))


def world(env: Environment, tool: str, **args: object) -> Any:
    return ok(env.call("env", f"shopping__{tool}", args))


def ids(listing: list[dict], key: str = "product_id") -> list[str]:
    return [row[key] for row in listing]


def drain(env: Environment) -> None:
    env.user_view()
    env.assistant_observation()


# -- seed data -----------------------------------------------------------------------------------------


def broken(change: str) -> dict:
    seed = copy.deepcopy(SEED)
    shop = seed["shopping"]
    if change == "variant key":
        shop["products"]["prod-mug"]["variants"]["mug-red"] = shop["products"]["prod-mug"]["variants"][
            "mug-blue"
        ]
    elif change == "variant product":
        shop["products"]["prod-mug"]["variants"]["mug-blue"]["product_id"] = "prod-kettle"
    elif change == "price decimals":
        shop["products"]["prod-mug"]["variants"]["mug-blue"]["price"] = 8.505
    elif change == "negative stock":
        shop["products"]["prod-mug"]["variants"]["mug-blue"]["stock"] = -1
    elif change == "shared item id":
        shop["products"]["prod-kettle"]["variants"] = {
            "mug-blue": {"item_id": "mug-blue", "name": "x", "price": 1, "stock": 1}
        }
    elif change == "cart item":
        shop["cart"]["ghost-item"] = 1
    elif change == "cart quantity":
        shop["cart"]["mug-blue"] = 0
    elif change == "both discounts":
        shop["discount_codes"]["WELCOME10"]["percent_off"] = 10
    elif change == "no discount":
        del shop["discount_codes"]["WELCOME10"]["amount_off"]
    elif change == "percent over 100":
        shop["discount_codes"]["STAFF30"]["percent_off"] = 130
    elif change == "twin codes":
        shop["discount_codes"]["spring15"] = {**shop["discount_codes"]["SPRING15"], "code": "spring15"}
    elif change == "order total":
        shop["orders"]["order-1"]["total"] = 16.00
    elif change == "order subtotal":
        shop["orders"]["order-1"]["subtotal"] = 18.00
    elif change == "order status":
        shop["orders"]["order-1"]["status"] = "lost"
    return seed


@pytest.mark.parametrize(
    ("change", "message"),
    [
        ("variant key", "has item_id 'mug-blue'"),
        ("variant product", "has product_id 'prod-kettle'"),
        ("price decimals", "at most two decimals"),
        ("negative stock", "stock"),
        ("shared item id", "used by two variants"),
        ("cart item", "'ghost-item'"),
        ("cart quantity", "start at 1"),
        ("both discounts", "exactly one of percent_off and amount_off"),
        ("no discount", "exactly one of percent_off and amount_off"),
        ("percent over 100", "at most 100"),
        ("twin codes", "codes ignore case"),
        ("order total", "total must be subtotal minus discount"),
        ("order subtotal", "not the sum of its items"),
        ("order status", "status"),
    ],
)
def test_seed_data_is_checked(change: str, message: str) -> None:
    with pytest.raises(UserInputError, match=message):
        make_env(["shopping"], broken(change))


def test_seed_variants_may_leave_out_their_product_id(env: Environment) -> None:
    assert data(env)["products"]["prod-mug"]["variants"]["mug-blue"]["product_id"] == "prod-mug"
    assert data(env)["orders"]["order-1"]["updated_at"] == "2025-02-10T18:30:00Z"  # defaults to placed_at


# -- Home ----------------------------------------------------------------------------------------------


def test_opens_on_home(env: Environment) -> None:
    assert screen_of(env) == "Home"


def test_list_products_pages_sorted_by_name(env: Environment) -> None:
    page = ok(env.call("user", "list_products", {"limit": 3}))
    assert ids(page["products"]) == ["prod-mug", "prod-daypack", "prod-kettle"]
    assert page["total"] == 12 and page["offset"] == 0
    first = page["products"][0]
    assert (first["name"], first["brand"], first["min_price"], first["max_price"]) == (
        "Ceramic Mug",
        "Hearth",
        8.5,
        8.5,
    )
    page = ok(env.call("user", "list_products", {"offset": 8, "limit": 2}))
    assert ids(page["products"]) == ["prod-trail", "prod-trail-gtx"]
    assert ids(ok(env.call("user", "list_products", {"offset": 10}))["products"]) == [
        "prod-charger",
        "prod-yoga",
    ]
    assert screen_of(env) == "Home"
    assert env.log[-1].kind == "read"


def test_listing_shows_price_range_and_availability(env: Environment) -> None:
    listed = {p["product_id"]: p for p in ok(env.call("user", "list_products", {"limit": 20}))["products"]}
    assert (listed["prod-trail"]["min_price"], listed["prod-trail"]["max_price"]) == (89.99, 94.99)
    assert listed["prod-trail"]["variant_count"] == 3
    # black is in stock, silver is not: the listing says which, not a plain "in stock", with the item ids
    # add_to_cart takes, so that ordering from a search needs no lookup per product
    assert (listed["prod-headphones"]["in_stock"], listed["prod-headphones"]["out_of_stock"]) == (
        [{"item_id": "hp-black", "name": "Black", "price": 199.0}],
        [{"item_id": "hp-silver", "name": "Silver", "price": 199.0}],
    )
    assert [v["name"] for v in listed["prod-trail"]["out_of_stock"]] == ["Blue / 43"]
    world(env, "update_item_stock", item_id="hp-black", new_stock=0)
    listed = {p["product_id"]: p for p in ok(env.call("user", "list_products", {"limit": 20}))["products"]}
    assert listed["prod-headphones"]["in_stock"] == []
    assert [v["item_id"] for v in listed["prod-headphones"]["out_of_stock"]] == ["hp-black", "hp-silver"]
    found = ok(env.call("user", "search_products", {"query": "headphones"}))
    assert found[0]["in_stock"] == []
    assert [v["name"] for v in found[0]["out_of_stock"]] == ["Black", "Silver"]


def test_a_searched_variant_goes_into_the_cart_by_the_item_id_the_search_gave(env: Environment) -> None:
    found = agent(env, "search_product", product_name="headphones")
    item_id = found[0]["in_stock"][0]["item_id"]
    cart = agent(env, "add_to_cart", item_id=item_id)
    assert item_id in [line["item_id"] for line in cart["lines"]]


def test_search_products_matches_every_word(env: Environment) -> None:
    assert ids(ok(env.call("user", "search_products", {"query": "trail"}))) == [
        "prod-trail",
        "prod-trail-gtx",
    ]
    assert ids(ok(env.call("user", "search_products", {"query": "TRAIL waterproof"}))) == ["prod-trail-gtx"]
    assert ids(ok(env.call("user", "search_products", {"query": "stride shoes"}))) == [
        "prod-road",
        "prod-trail",
        "prod-trail-gtx",
    ]  # brand and category
    assert ids(ok(env.call("user", "search_products", {"query": "dishwasher"}))) == [
        "prod-mug"
    ]  # description
    assert ids(ok(env.call("user", "search_products", {"query": "northline"}))) == [
        "prod-daypack",
        "prod-hoodie",
        "prod-yoga",
    ]
    assert ok(env.call("user", "search_products", {"query": "toaster"})) == []
    err(env.call("user", "search_products", {"query": "  "}), "empty")
    assert screen_of(env) == "Home"


def test_view_product_goes_to_product(env: Environment) -> None:
    shown = ok(env.call("user", "view_product", {"product_id": "prod-hoodie"}))
    assert shown["name"] == "Everyday Hoodie"
    assert list(shown["variants"]) == ["hoodie-blue-m", "hoodie-blue-l", "hoodie-grey-m"]
    assert shown["variants"]["hoodie-blue-l"]["stock"] == 1
    assert screen_of(env) == "Product"
    assert stack(env) == ["Home", "Product"]


def test_view_unknown_product_is_an_error_and_stays(env: Environment) -> None:
    err(env.call("user", "view_product", {"product_id": "prod-toaster"}), "no product with id 'prod-toaster'")
    assert screen_of(env) == "Home"


def test_view_cart_goes_to_cart(env: Environment) -> None:
    cart = ok(env.call("user", "view_cart"))
    assert screen_of(env) == "Cart"
    assert ids(cart["lines"], "item_id") == ["trail-blue-42", "hoodie-blue-m"]
    assert cart["subtotal"] == CART_SUBTOTAL
    assert cart["item_count"] == 3


def test_list_orders_goes_to_orders_newest_first(env: Environment) -> None:
    shown = ok(env.call("user", "list_orders"))
    assert screen_of(env) == "Orders"
    assert ids(shown, "order_id") == ["order-4", "order-3", "order-2", "order-1", "order-5"]
    assert ids(ok(env.call("user", "list_orders")), "order_id")[0] == "order-4"  # the Orders screen's own
    assert screen_of(env) == "Orders"


# -- Product and Variant -------------------------------------------------------------------------------


def test_product_view_product_shows_the_current_data(env: Environment) -> None:
    ok(env.call("user", "view_product", {"product_id": "prod-trail"}))
    world(env, "update_item_price", item_id="trail-black-42", new_price=79.99)
    shown = ok(env.call("user", "view_product"))
    assert shown["variants"]["trail-black-42"]["price"] == 79.99
    assert screen_of(env) == "Product"


def test_view_variant_goes_to_variant(env: Environment) -> None:
    ok(env.call("user", "view_product", {"product_id": "prod-trail"}))
    shown = ok(env.call("user", "view_variant", {"item_id": "trail-blue-42"}))
    assert shown == {
        "item_id": "trail-blue-42",
        "product_id": "prod-trail",
        "product_name": "Trail Runner 3",
        "brand": "Stride",
        "variant_name": "Blue / 42",
        "options": {"color": "Blue", "size": "42"},
        "price": 89.99,
        "stock": 5,
        "in_cart": 1,
    }
    assert screen_of(env) == "Variant"
    assert stack(env) == ["Home", "Product", "Variant"]
    assert ok(env.call("user", "view_variant"))["item_id"] == "trail-blue-42"
    assert screen_of(env) == "Variant"


@pytest.mark.parametrize("item_id", ["gtx-grey-42", "ghost"])
def test_view_variant_of_another_product_is_an_error(env: Environment, item_id: str) -> None:
    ok(env.call("user", "view_product", {"product_id": "prod-trail"}))
    err(
        env.call("user", "view_variant", {"item_id": item_id}),
        f"'{item_id}' is not a variant of trail runner 3",
        "trail-black-42 (Black / 42)",
    )
    assert screen_of(env) == "Product"


def test_add_to_cart_from_variant_opens_the_cart(env: Environment) -> None:
    ok(env.call("user", "view_product", {"product_id": "prod-mug"}))
    ok(env.call("user", "view_variant", {"item_id": "mug-white"}))
    cart = ok(env.call("user", "add_to_cart", {"quantity": 3}))
    assert screen_of(env) == "Cart"
    assert stack(env) == ["Home", "Product", "Variant", "Cart"]
    assert env.log[-1].kind == "write"
    assert data(env)["cart"] == {"trail-blue-42": 1, "hoodie-blue-m": 2, "mug-white": 3}
    assert cart["lines"][-1] == {
        "item_id": "mug-white",
        "product_id": "prod-mug",
        "product_name": "Ceramic Mug",
        "variant_name": "White",
        "unit_price": 8.5,
        "quantity": 3,
        "line_total": 25.5,
        "stock": 40,
    }
    assert cart["subtotal"] == 214.49
    assert stock(env, "prod-mug", "mug-white") == 40  # stock moves only at checkout
    ok(env.call("user", "go_back"))
    assert ok(env.call("user", "add_to_cart"))["lines"][-1]["quantity"] == 4  # default 1, same line


@pytest.mark.parametrize(
    ("item_id", "quantity", "message"),
    [
        ("trail-blue-42", 5, "only 5 of trail runner 3 (blue / 42) in stock and 1 already in the cart"),
        ("hoodie-blue-l", 2, "at most 1"),
        ("trail-blue-43", 1, "out of stock"),
        ("trail-black-42", 0, "at least 1"),
    ],
)
def test_add_to_cart_errors_change_nothing(
    env: Environment, item_id: str, quantity: int, message: str
) -> None:
    product_id = "prod-hoodie" if item_id.startswith("hoodie") else "prod-trail"
    ok(env.call("user", "view_product", {"product_id": product_id}))
    ok(env.call("user", "view_variant", {"item_id": item_id}))
    before = env.snapshot()
    err(env.call("user", "add_to_cart", {"quantity": quantity}), message)
    assert env.snapshot() == before
    assert screen_of(env) == "Variant"


# -- Cart ----------------------------------------------------------------------------------------------


def test_remove_item_reduces_then_drops_the_line(env: Environment) -> None:
    ok(env.call("user", "view_cart"))
    cart = ok(env.call("user", "remove_item", {"item_id": "hoodie-blue-m"}))
    assert screen_of(env) == "Cart"
    assert env.log[-1].kind == "write"
    assert data(env)["cart"] == {"trail-blue-42": 1, "hoodie-blue-m": 1}
    assert cart["subtotal"] == 139.49
    cart = ok(env.call("user", "remove_item", {"item_id": "hoodie-blue-m", "quantity": 1}))
    assert ids(cart["lines"], "item_id") == ["trail-blue-42"]
    assert data(env)["cart"] == {"trail-blue-42": 1}
    assert ok(env.call("user", "view_cart"))["subtotal"] == 89.99
    assert screen_of(env) == "Cart"


@pytest.mark.parametrize(
    ("args", "message"),
    [
        ({"item_id": "mug-white"}, "'mug-white' is not in the cart"),
        ({"item_id": "hoodie-blue-m", "quantity": 3}, "holds only 2"),
        ({"item_id": "hoodie-blue-m", "quantity": 0}, "at least 1"),
    ],
)
def test_remove_item_errors_change_nothing(env: Environment, args: dict, message: str) -> None:
    ok(env.call("user", "view_cart"))
    before = env.snapshot()
    err(env.call("user", "remove_item", args), message)
    assert env.snapshot() == before
    assert screen_of(env) == "Cart"


def test_checkout_replaces_the_cart_by_the_new_order(env: Environment) -> None:
    ok(env.call("user", "view_cart"))
    placed = ok(env.call("user", "checkout"))
    assert screen_of(env) == "OrderDetail"
    assert stack(env) == ["Home", "OrderDetail"]
    assert env.log[-1].kind == "write"
    assert placed["order_id"] == "order-6"  # after the highest seeded order number
    assert placed == data(env)["orders"]["order-6"]
    assert placed["items"] == [
        {
            "item_id": "trail-blue-42",
            "product_name": "Trail Runner 3",
            "variant_name": "Blue / 42",
            "quantity": 1,
            "unit_price": 89.99,
        },
        {
            "item_id": "hoodie-blue-m",
            "product_name": "Everyday Hoodie",
            "variant_name": "Blue / M",
            "quantity": 2,
            "unit_price": 49.5,
        },
    ]
    assert (placed["subtotal"], placed["discount"], placed["total"]) == (188.99, 0, 188.99)
    assert placed["discount_code"] is None
    assert placed["status"] == "placed"
    assert placed["placed_at"] == placed["updated_at"] == "2025-03-03T09:00:00Z"
    assert data(env)["cart"] == {}
    assert stock(env, "prod-trail", "trail-blue-42") == 4
    assert stock(env, "prod-hoodie", "hoodie-blue-m") == 8
    assert ok(env.call("user", "view_order"))["order_id"] == "order-6"
    ok(env.call("user", "go_back"))
    assert screen_of(env) == "Home"
    assert ok(env.call("user", "view_cart"))["lines"] == []


def test_checkout_from_the_variant_flow(env: Environment) -> None:
    ok(env.call("user", "view_product", {"product_id": "prod-daypack"}))
    ok(env.call("user", "view_variant", {"item_id": "pack-green"}))
    ok(env.call("user", "add_to_cart"))
    placed = ok(env.call("user", "checkout", {"discount_code": "spring15"}))
    assert stack(env) == ["Home", "Product", "Variant", "OrderDetail"]
    # 89.99 + 99.00 + 64.00 = 252.99; 15% of it is 37.9485, rounded to 37.95
    assert (placed["subtotal"], placed["discount"], placed["total"]) == (252.99, 37.95, 215.04)
    assert placed["discount_code"] == "SPRING15"  # stored as the store spells it


@pytest.mark.parametrize(
    ("code", "message"),
    [
        ("NOPE", "no discount code 'nope'"),
        ("STAFF30", "'staff30' is no longer active"),
        ("winter20", "'winter20' expired at 2025-02-28 23:59"),
        ("BIGSPEND50", "needs a subtotal of at least $250.00; the cart's subtotal is $188.99"),
    ],
)
def test_checkout_with_a_refused_code_changes_nothing(env: Environment, code: str, message: str) -> None:
    ok(env.call("user", "view_cart"))
    before = env.snapshot()
    err(env.call("user", "checkout", {"discount_code": code}), message)
    assert env.snapshot() == before
    assert screen_of(env) == "Cart"


def test_checkout_with_an_empty_cart_is_an_error(env: Environment) -> None:
    ok(env.call("user", "view_cart"))
    ok(env.call("user", "remove_item", {"item_id": "trail-blue-42"}))
    ok(env.call("user", "remove_item", {"item_id": "hoodie-blue-m", "quantity": 2}))
    before = env.snapshot()
    err(env.call("user", "checkout"), "cart is empty")
    assert env.snapshot() == before
    assert screen_of(env) == "Cart"


def test_checkout_rechecks_stock(env: Environment) -> None:
    world(env, "update_item_stock", item_id="hoodie-blue-m", new_stock=1)
    world(env, "update_item_stock", item_id="trail-blue-42", new_stock=0)
    ok(env.call("user", "view_cart"))
    assert [line["stock"] for line in ok(env.call("user", "view_cart"))["lines"]] == [0, 1]
    before = env.snapshot()
    err(
        env.call("user", "checkout"),
        "not enough stock",
        "trail runner 3 (blue / 42) (1 in the cart, 0 in stock)",
        "everyday hoodie (blue / m) (2 in the cart, 1 in stock)",
    )
    assert env.snapshot() == before
    assert screen_of(env) == "Cart"


# -- Orders and OrderDetail ----------------------------------------------------------------------------


def test_view_order_goes_to_order_detail(env: Environment) -> None:
    ok(env.call("user", "list_orders"))
    shown = ok(env.call("user", "view_order", {"order_id": "order-2"}))
    assert (shown["status"], shown["discount_code"], shown["total"]) == ("shipped", "WELCOME10", 19.99)
    assert screen_of(env) == "OrderDetail"
    assert stack(env) == ["Home", "Orders", "OrderDetail"]
    world(env, "update_order_status", order_id="order-2", status="delivered")
    assert ok(env.call("user", "view_order"))["status"] == "delivered"
    assert screen_of(env) == "OrderDetail"


def test_view_unknown_order_is_an_error_and_stays(env: Environment) -> None:
    ok(env.call("user", "list_orders"))
    err(env.call("user", "view_order", {"order_id": "order-99"}), "no order with id 'order-99'")
    assert screen_of(env) == "Orders"


@pytest.mark.parametrize("order_id", ["order-3", "order-4"])
def test_cancel_order_restores_stock(env: Environment, order_id: str) -> None:
    env.advance(timedelta(minutes=30))
    ok(env.call("user", "list_orders"))
    ok(env.call("user", "view_order", {"order_id": order_id}))
    before = {
        item: stock(env, p, item)
        for p, item in [("prod-charger", "charger-white"), ("prod-socks", "socks-m")]
    }
    hoodie = stock(env, "prod-hoodie", "hoodie-grey-m")
    cancelled = ok(env.call("user", "cancel_order"))
    assert screen_of(env) == "OrderDetail"
    assert env.log[-1].kind == "write"
    assert cancelled["status"] == "cancelled"
    assert cancelled["updated_at"] == "2025-03-03T09:30:00Z"
    assert data(env)["orders"][order_id]["status"] == "cancelled"
    if order_id == "order-3":
        assert stock(env, "prod-charger", "charger-white") == before["charger-white"] + 1
        assert stock(env, "prod-socks", "socks-m") == before["socks-m"] + 1
    else:
        assert stock(env, "prod-hoodie", "hoodie-grey-m") == hoodie + 1


@pytest.mark.parametrize(
    ("order_id", "message"),
    [("order-2", "is shipped"), ("order-1", "is delivered"), ("order-5", "is cancelled")],
)
def test_orders_past_processing_cannot_be_cancelled(env: Environment, order_id: str, message: str) -> None:
    ok(env.call("user", "list_orders"))
    ok(env.call("user", "view_order", {"order_id": order_id}))
    before = env.snapshot()
    err(env.call("user", "cancel_order"), message, "only placed or processing")
    assert env.snapshot() == before
    assert screen_of(env) == "OrderDetail"


# -- agent API -----------------------------------------------------------------------------------------


def test_agent_reads(env: Environment) -> None:
    page = agent(env, "list_all_products", offset=2, limit=2)
    assert ids(page["products"]) == ["prod-kettle", "prod-hoodie"]
    assert page["total"] == 12 and page["offset"] == 2
    assert ids(agent(env, "search_product", product_name="running shoe")) == ["prod-road", "prod-trail"]
    details = agent(env, "get_product_details", product_id="prod-bottle")
    assert {k: (v["price"], v["stock"]) for k, v in details["variants"].items()} == {
        "bottle-500": (24.0, 20),
        "bottle-750": (28.0, 0),
    }
    cart = agent(env, "list_cart")
    assert [
        (line["item_id"], line["unit_price"], line["quantity"], line["line_total"]) for line in cart["lines"]
    ] == [
        ("trail-blue-42", 89.99, 1, 89.99),
        ("hoodie-blue-m", 49.5, 2, 99.0),
    ]
    assert cart["subtotal"] == CART_SUBTOTAL
    orders = agent(env, "list_orders")
    assert ids(orders, "order_id") == ["order-4", "order-3", "order-2", "order-1", "order-5"]
    assert agent(env, "get_order_details", order_id="order-3")["subtotal"] == 49.98


def test_agent_cart_and_checkout(env: Environment) -> None:
    cart = agent(env, "add_to_cart", item_id="socks-l", quantity=2)
    assert ids(cart["lines"], "item_id") == ["trail-blue-42", "hoodie-blue-m", "socks-l"]
    assert cart["subtotal"] == 218.97
    cart = agent(env, "remove_from_cart", item_id="trail-blue-42")
    assert ids(cart["lines"], "item_id") == ["hoodie-blue-m", "socks-l"]
    placed = agent(env, "checkout", discount_code="  welcome10 ")
    assert (placed["subtotal"], placed["discount"], placed["total"]) == (128.98, 10.0, 118.98)
    assert placed["discount_code"] == "WELCOME10"
    assert data(env)["cart"] == {}
    assert stock(env, "prod-socks", "socks-l") == 23
    assert stock(env, "prod-trail", "trail-blue-42") == 5  # removed before checkout
    assert agent(env, "list_orders")[0]["order_id"] == placed["order_id"]
    cancelled = agent(env, "cancel_order", order_id=placed["order_id"])
    assert cancelled["status"] == "cancelled"
    assert stock(env, "prod-socks", "socks-l") == 25
    assert stock(env, "prod-hoodie", "hoodie-blue-m") == 10


def test_checkout_rounds_half_up_in_cents(env: Environment) -> None:
    agent(env, "remove_from_cart", item_id="trail-blue-42")
    agent(env, "remove_from_cart", item_id="hoodie-blue-m", quantity=2)
    agent(env, "add_to_cart", item_id="mug-white")
    # 5% of 8.50 is 0.425: half-up gives 0.43 (banker's rounding would give 0.42)
    assert agent(env, "get_discount_code_info", code="flash5")["discount_on_cart"] == 0.43
    placed = agent(env, "checkout", discount_code="FLASH5")
    assert (placed["subtotal"], placed["discount"], placed["total"]) == (8.5, 0.43, 8.07)


def test_a_fixed_discount_never_exceeds_the_subtotal(env: Environment) -> None:
    agent(env, "remove_from_cart", item_id="trail-blue-42")
    agent(env, "remove_from_cart", item_id="hoodie-blue-m", quantity=2)
    agent(env, "add_to_cart", item_id="mug-blue")
    placed = agent(env, "checkout", discount_code="WELCOME10")
    assert (placed["subtotal"], placed["discount"], placed["total"]) == (8.5, 8.5, 0)


def test_discount_code_info_and_listing(env: Environment) -> None:
    assert ids(agent(env, "get_all_discount_codes"), "code") == [
        "BIGSPEND50",
        "Flash5",
        "SPRING15",
        "WELCOME10",
    ]
    info = agent(env, "get_discount_code_info", code="spring15")
    assert info["code"] == "SPRING15" and info["percent_off"] == 15 and info["min_subtotal"] == 50
    assert (info["usable_now"], info["problem"], info["discount_on_cart"]) == (True, None, 28.35)
    info = agent(env, "get_discount_code_info", code="BIGSPEND50")
    assert info["usable_now"] is False and "at least $250.00" in info["problem"]
    assert info["discount_on_cart"] == 0
    assert "no longer active" in agent(env, "get_discount_code_info", code="staff30")["problem"]
    assert "expired" in agent(env, "get_discount_code_info", code="WINTER20")["problem"]
    agent(env, "remove_from_cart", item_id="trail-blue-42")
    agent(env, "remove_from_cart", item_id="hoodie-blue-m", quantity=2)
    assert agent(env, "get_discount_code_info", code="welcome10")["problem"] == "The cart is empty."


def test_codes_expire_with_the_simulated_clock(env: Environment) -> None:
    assert agent(env, "get_discount_code_info", code="flash5")["usable_now"] is True
    env.advance(timedelta(hours=3))  # 12:00, when FLASH5 stops
    assert "Flash5" not in ids(agent(env, "get_all_discount_codes"), "code")
    before = env.snapshot()
    err(env.call("assistant", "shopping__checkout", {"discount_code": "flash5"}, mode="execute"), "expired")
    assert env.snapshot() == before


@pytest.mark.parametrize(
    ("tool", "args", "message"),
    [
        ("list_all_products", {"limit": 0}, "limit"),
        ("list_all_products", {"offset": -1}, "offset"),
        ("search_product", {"product_name": " "}, "empty"),
        ("get_product_details", {"product_id": "prod-toaster"}, "no product with id 'prod-toaster'"),
        ("add_to_cart", {"item_id": "ghost"}, "no item with id 'ghost'"),
        ("add_to_cart", {"item_id": "hp-silver"}, "out of stock"),
        ("add_to_cart", {"item_id": "trail-black-42", "quantity": 3}, "only 2"),
        ("add_to_cart", {"item_id": "mug-white", "quantity": -2}, "at least 1"),
        ("remove_from_cart", {"item_id": "mug-white"}, "not in the cart"),
        ("remove_from_cart", {"item_id": "trail-blue-42", "quantity": 2}, "holds only 1"),
        ("checkout", {"discount_code": "HALFOFF"}, "no discount code 'halfoff'"),
        ("checkout", {"discount_code": "staff30"}, "no longer active"),
        ("checkout", {"discount_code": "WINTER20"}, "expired"),
        ("checkout", {"discount_code": "bigspend50"}, "needs a subtotal of at least $250.00"),
        ("get_discount_code_info", {"code": "HALFOFF"}, "get_all_discount_codes"),
        ("get_order_details", {"order_id": "order-99"}, "list_orders"),
        ("cancel_order", {"order_id": "order-99"}, "no order"),
        ("cancel_order", {"order_id": "order-2"}, "can no longer be cancelled"),
    ],
)
def test_agent_api_errors_change_nothing(env: Environment, tool: str, args: dict, message: str) -> None:
    before = env.snapshot()
    err(env.call("assistant", f"shopping__{tool}", args, mode="execute"), message)
    assert env.snapshot() == before


def test_writes_need_execute_mode(env: Environment) -> None:
    err(env.call("assistant", "shopping__checkout", {}, mode="observe"), "execute mode")
    assert ok(env.call("assistant", "shopping__list_cart", {}, mode="observe"))["subtotal"] == CART_SUBTOTAL


# -- the world -----------------------------------------------------------------------------------------


def test_price_drop_on_a_cart_item_notifies_both(env: Environment) -> None:
    drain(env)
    variant = world(env, "update_item_price", item_id="trail-blue-42", new_price=74.99)
    assert variant["price"] == 74.99
    assert data(env)["products"]["prod-trail"]["variants"]["trail-blue-42"]["price"] == 74.99
    assert agent(env, "list_cart")["subtotal"] == 173.99
    assert data(env)["orders"]["order-1"]["items"][0]["unit_price"] == 8.5  # orders keep their prices

    user = env.user_view().notifications
    assert len(user) == 1
    assert "Price drop on Trail Runner 3 (Blue / 42)" in user[0] and "Now $74.99, was $89.99" in user[0]
    assert "$15.00 less each" not in user[0]  # the user's copy is cut
    assistant = env.assistant_observation().notifications
    assert len(assistant) == 1
    assert "$15.00 less each" in assistant[0]
    assert "item_id=trail-blue-42" in assistant[0] and "old_price=89.99" in assistant[0]


@pytest.mark.parametrize(
    ("item_id", "new_price"), [("trail-blue-42", 99.99), ("trail-blue-42", 89.99), ("gtx-grey-42", 99.0)]
)
def test_other_price_changes_are_silent(env: Environment, item_id: str, new_price: float) -> None:
    drain(env)
    assert world(env, "update_item_price", item_id=item_id, new_price=new_price)["price"] == new_price
    assert env.user_view().notifications == []
    assert env.assistant_observation().notifications == []


def test_back_in_stock_for_a_cart_item(env: Environment) -> None:
    world(env, "update_item_stock", item_id="hoodie-blue-m", new_stock=0)
    drain(env)
    assert world(env, "update_item_stock", item_id="hoodie-blue-m", new_stock=6)["stock"] == 6
    assert stock(env, "prod-hoodie", "hoodie-blue-m") == 6
    user = env.user_view().notifications
    assert len(user) == 1
    assert "Back in stock: Everyday Hoodie (Blue / M)" in user[0]
    assert "6 in stock" not in user[0]
    assistant = env.assistant_observation().notifications
    assert "the store has 6 in stock" in assistant[0] and "item_id=hoodie-blue-m" in assistant[0]


@pytest.mark.parametrize(
    ("item_id", "new_stock"),
    [("hp-silver", 4), ("trail-blue-42", 9), ("trail-blue-42", 0)],  # not in the cart; in stock already
)
def test_other_stock_changes_are_silent(env: Environment, item_id: str, new_stock: int) -> None:
    drain(env)
    world(env, "update_item_stock", item_id=item_id, new_stock=new_stock)
    assert env.user_view().notifications == []
    assert env.assistant_observation().notifications == []


def test_add_discount_code_notifies_and_is_usable(env: Environment) -> None:
    drain(env)
    added = world(
        env,
        "add_discount_code",
        code="TREK25",
        description="Trail week",
        percent_off=25,
        min_subtotal=100,
        expires_at="2025-03-07 23:59",
    )
    assert added["code"] == "TREK25" and added["active"] is True
    assert data(env)["discount_codes"]["TREK25"]["expires_at"] == "2025-03-07T23:59:00Z"
    user = env.user_view().notifications
    assert len(user) == 1
    assert "New discount code TREK25" in user[0] and "Trail week" in user[0]
    assert "Enter TREK25 at checkout" not in user[0]
    assistant = env.assistant_observation().notifications
    assert "25% off orders of $100.00 or more, valid until 2025-03-07 23:59 UTC" in assistant[0]
    assert "code=TREK25" in assistant[0]
    assert agent(env, "checkout", discount_code="trek25")["discount"] == 47.25


def test_add_fixed_amount_code(env: Environment) -> None:
    drain(env)
    world(env, "add_discount_code", code="FIVER", description="Sorry for the delay", amount_off=5)
    assert "$5.00 off any order" in env.assistant_observation().notifications[0]


@pytest.mark.parametrize(
    ("args", "message"),
    [
        ({"code": "spring15", "percent_off": 10}, "already exists"),
        ({"code": " ", "percent_off": 10}, "cannot be empty"),
        ({"code": "NEW"}, "exactly one of percent_off and amount_off"),
        ({"code": "NEW", "percent_off": 10, "amount_off": 5}, "exactly one"),
        ({"code": "NEW", "percent_off": 0}, "above 0"),
        ({"code": "NEW", "amount_off": 5.555}, "two decimals"),
        ({"code": "NEW", "amount_off": 5, "min_subtotal": -1}, "negative"),
        ({"code": "NEW", "amount_off": 5, "expires_at": "2025-03-03 08:00"}, "not in the future"),
    ],
)
def test_add_discount_code_errors_change_nothing(env: Environment, args: dict, message: str) -> None:
    drain(env)
    before = env.snapshot()
    err(env.call("env", "shopping__add_discount_code", {"description": "x", **args}), message)
    assert env.snapshot() == before
    assert env.user_view().notifications == []


@pytest.mark.parametrize(
    ("order_id", "status", "headline"),
    [
        ("order-4", "processing", "Your order order-4 is being processed"),
        ("order-4", "shipped", "Your order order-4 has shipped"),  # a step may be skipped
        ("order-3", "shipped", "Your order order-3 has shipped"),
        ("order-2", "delivered", "Your order order-2 has been delivered"),
    ],
)
def test_order_status_moves_forward_and_notifies(
    env: Environment, order_id: str, status: str, headline: str
) -> None:
    env.advance(timedelta(hours=2))
    drain(env)
    moved = world(env, "update_order_status", order_id=order_id, status=status)
    assert moved["status"] == status == data(env)["orders"][order_id]["status"]
    assert moved["updated_at"] == "2025-03-03T11:00:00Z"
    user = env.user_view().notifications
    assert len(user) == 1 and headline in user[0]
    assistant = env.assistant_observation().notifications
    assert f"order_id={order_id}" in assistant[0] and f"status={status}" in assistant[0]


def test_order_status_notification_lists_the_items(env: Environment) -> None:
    drain(env)
    world(env, "update_order_status", order_id="order-3", status="shipped")
    assistant = env.assistant_observation().notifications[0]
    assert "2 items, total $49.98: 1 x USB-C Charger 65W (White), 1 x Running Socks 3-pack (M)." in assistant


def test_the_store_cancelling_an_order_restores_stock(env: Environment) -> None:
    drain(env)
    world(env, "update_order_status", order_id="order-3", status="cancelled")
    assert data(env)["orders"]["order-3"]["status"] == "cancelled"
    assert stock(env, "prod-charger", "charger-white") == 16
    assert stock(env, "prod-socks", "socks-m") == 31
    assert "Your order order-3 was cancelled" in env.user_view().notifications[0]


@pytest.mark.parametrize(
    ("order_id", "status", "message"),
    [
        ("order-99", "shipped", "no order"),
        ("order-2", "shipped", "already shipped"),
        ("order-2", "processing", "cannot go from shipped to processing"),
        ("order-1", "cancelled", "only placed or processing"),
        ("order-5", "placed", "cannot go from cancelled to placed"),
        ("order-5", "delivered", "cannot go from cancelled"),
        ("order-4", "lost", "status"),
    ],
)
def test_update_order_status_errors_change_nothing(
    env: Environment, order_id: str, status: str, message: str
) -> None:
    drain(env)
    before = env.snapshot()
    err(env.call("env", "shopping__update_order_status", {"order_id": order_id, "status": status}), message)
    assert env.snapshot() == before
    assert env.user_view().notifications == []


@pytest.mark.parametrize(
    ("tool", "args", "message"),
    [
        ("update_item_price", {"item_id": "ghost", "new_price": 1}, "no item"),
        ("update_item_price", {"item_id": "mug-white", "new_price": -1}, "negative"),
        ("update_item_price", {"item_id": "mug-white", "new_price": 1.234}, "two decimals"),
        ("update_item_stock", {"item_id": "ghost", "new_stock": 1}, "no item"),
        ("update_item_stock", {"item_id": "mug-white", "new_stock": -3}, "negative"),
    ],
)
def test_item_update_errors_change_nothing(env: Environment, tool: str, args: dict, message: str) -> None:
    before = env.snapshot()
    err(env.call("env", f"shopping__{tool}", args), message)
    assert env.snapshot() == before


def test_add_product(env: Environment) -> None:
    drain(env)
    added = world(
        env,
        "add_product",
        name="Trail Runner 4",
        brand="Stride",
        category="Shoes",
        description="The new trail shoe.",
        product_id="prod-trail-4",
        variants=[
            {"name": "Red / 42", "price": 139.0, "stock": 4, "options": {"color": "Red", "size": "42"}},
            {"name": "Red / 43", "price": 139.0, "item_id": "t4-red-43"},
        ],
    )
    assert list(added["variants"]) == ["item-1", "t4-red-43"]
    assert added["variants"]["item-1"]["product_id"] == "prod-trail-4"
    assert added["variants"]["t4-red-43"]["stock"] == 0
    assert "prod-trail-4" in ids(agent(env, "search_product", product_name="trail runner"))
    agent(env, "add_to_cart", item_id="item-1", quantity=4)
    assert env.user_view().notifications == []
    auto = world(env, "add_product", name="Gift Card", variants=[{"name": "25", "price": 25}])
    assert auto["product_id"] == "product-1" and list(auto["variants"]) == ["item-2"]


@pytest.mark.parametrize(
    ("args", "message"),
    [
        ({"name": " "}, "needs a name"),
        ({"variants": []}, "at least one variant"),
        ({"product_id": "prod-mug"}, "already exists"),
        ({"variants": [{"name": "A", "price": 1, "item_id": "mug-white"}]}, "'mug-white' already exists"),
        ({"variants": [{"name": "A", "price": 1, "item_id": "x"}, {"name": "B", "price": 1, "item_id": "x"}]},
         "'x' already exists"),
        ({"variants": [{"name": "A", "price": 1.001}]}, "two decimals"),
        ({"variants": [{"name": " ", "price": 1}]}, "needs a name"),
    ],
)  # fmt: skip
def test_add_product_errors_change_nothing(env: Environment, args: dict, message: str) -> None:
    before = env.snapshot()
    call = {"name": "Thing", "variants": [{"name": "One", "price": 1}], **args}
    err(env.call("env", "shopping__add_product", call), message)
    assert env.snapshot() == before


def test_world_tools_are_not_for_the_assistant_or_the_user(env: Environment) -> None:
    args = {"item_id": "mug-white", "new_price": 1.0}
    err(env.call("assistant", "shopping__update_item_price", args, mode="execute"), "not available")
    err(env.call("user", "update_item_price", args), "unknown action")


# -- the random user -----------------------------------------------------------------------------------


def test_a_random_user_walks_every_screen_without_breaking() -> None:
    env = make_env(["shopping"], SEED)
    user = RandomUser(random.Random(0))
    for _ in range(3000):
        user.step(env)  # raise_internal_errors: a crash or an undeclared transition fails the test
    screens = {entry.app_screen[1] for entry in env.log if entry.app_screen}
    assert {"Home", "Product", "Variant", "Cart", "Orders", "OrderDetail"} <= screens
    assert sum(entry.ok for entry in env.log) / len(env.log) > 0.5


def test_a_six_item_order_fits_the_execute_budget_with_the_ids_a_listing_gives(env: Environment) -> None:
    """One listing gives every in-stock variant's item id, so six items, the checkout and the report take
    9 of the 10 execute actions (no lookup per product, no guessed ids).
    """
    agent(env, "remove_from_cart", item_id="trail-blue-42")
    agent(env, "remove_from_cart", item_id="hoodie-blue-m", quantity=2)
    calls = 1
    listing = agent(env, "list_all_products", limit=100)
    wanted = [product["in_stock"][0]["item_id"] for product in listing["products"] if product["in_stock"]][:6]
    assert len(wanted) == 6
    for item_id in wanted:
        agent(env, "add_to_cart", item_id=item_id)
        calls += 1
    order = agent(env, "checkout")
    calls += 1
    assert sorted(item["item_id"] for item in order["items"]) == sorted(wanted)
    assert calls + 1 <= EpisodeSettings().execute_steps  # and the report to the user
