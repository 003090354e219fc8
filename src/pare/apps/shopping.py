"""Shopping: an online store's products and their variants, the user's cart, discount codes and orders."""

# Screen actions take the app as their second argument; the framework passes it and models never see it,
# so it is not described in their docstrings.

from __future__ import annotations

from collections.abc import Iterable
from datetime import datetime
from decimal import ROUND_HALF_UP, Decimal
from typing import Any, Literal

from pydantic import BaseModel, ConfigDict, Field, ValidationError, field_validator, model_validator

from pare.apps.base import App, DatedRecord
from pare.apps.paging import Paged, showing_screen
from pare.apps.screens import Screen, Transition, action, push, replace
from pare.apps.text import PAGE, short_time
from pare.apps.tools import tool
from pare.apps.types import SimTime
from pare.errors import ToolError
from pare.sim.clock import ensure_utc

OrderStatus = Literal["placed", "processing", "shipped", "delivered", "cancelled"]
"""Where an order is: placed -> processing -> shipped -> delivered, or cancelled before it ships."""

_PROGRESS: tuple[OrderStatus, ...] = ("placed", "processing", "shipped", "delivered")
"""The forward path of an order; cancellation is possible from the first two."""

_CANCELLABLE: tuple[OrderStatus, ...] = ("placed", "processing")

_STATUS_HEADLINES: dict[OrderStatus, str] = {
    "placed": "was placed",
    "processing": "is being processed",
    "shipped": "has shipped",
    "delivered": "has been delivered",
    "cancelled": "was cancelled",
}


# -- money ---------------------------------------------------------------------------------------------


def _cents(amount: float) -> int:
    """``amount`` in whole cents, rounded half-up."""
    return int((Decimal(str(amount)) * 100).quantize(Decimal(1), rounding=ROUND_HALF_UP))


def _is_whole_cents(amount: float) -> bool:
    """Whether ``amount`` has at most two decimals."""
    return (Decimal(str(amount)) * 100) % 1 == 0


def _amount(cents: int) -> float:
    """Cents as an amount with two decimals."""
    return cents / 100


def _fmt(cents: int) -> str:
    """Cents for people, e.g. ``$1,234.50``."""
    return f"${cents // 100:,}.{cents % 100:02d}"


def _check_money(value: float, what: str) -> float:
    """Raise a :class:`ValueError` unless ``value`` is a non-negative amount in whole cents."""
    if value < 0:
        raise ValueError(f"{what} cannot be negative (got {value})")
    if not _is_whole_cents(value):
        raise ValueError(f"{what} must have at most two decimals (got {value})")
    return value


def _percent_of(cents: int, percent: float) -> int:
    """``percent`` % of ``cents``, rounded half-up to a cent."""
    share = Decimal(cents) * Decimal(str(percent)) / 100
    return int(share.quantize(Decimal(1), rounding=ROUND_HALF_UP))


# -- data ----------------------------------------------------------------------------------------------


class Variant(BaseModel):
    """One buyable version of a product (a size, a colour): what goes into the cart, by its item id."""

    model_config = ConfigDict(extra="forbid")

    item_id: str
    product_id: str
    name: str = Field(description='e.g. "Blue / M"')
    options: dict[str, str] = Field(default_factory=dict, description='e.g. {"color": "Blue", "size": "M"}')
    price: float = Field(description="the unit price, >= 0, two decimals")
    stock: int = Field(ge=0, description="how many the store has")

    @field_validator("price")
    @classmethod
    def _price_in_cents(cls, value: float) -> float:
        return _check_money(value, "price")


class Product(BaseModel):
    """A product of the store with its variants by item id."""

    model_config = ConfigDict(extra="forbid")

    product_id: str
    name: str
    description: str = ""
    category: str = ""
    brand: str = ""
    variants: dict[str, Variant] = Field(default_factory=dict)

    @model_validator(mode="before")
    @classmethod
    def _variants_know_their_product(cls, data: Any) -> Any:
        """Let seed data leave out each variant's product_id: it is the product's."""
        if isinstance(data, dict) and isinstance(data.get("variants"), dict) and "product_id" in data:
            variants = {
                key: {"product_id": data["product_id"], **value} if isinstance(value, dict) else value
                for key, value in data["variants"].items()
            }
            data = {**data, "variants": variants}
        return data

    @model_validator(mode="after")
    def _variant_keys_are_ids(self) -> Product:
        for key, variant in self.variants.items():
            if key != variant.item_id:
                raise ValueError(f"variant stored under '{key}' has item_id '{variant.item_id}'")
            if variant.product_id != self.product_id:
                raise ValueError(
                    f"variant '{key}' of product '{self.product_id}' has product_id '{variant.product_id}'"
                )
        return self


class DiscountCode(BaseModel):
    """A discount code for checkout: a percentage or a fixed amount off the subtotal."""

    model_config = ConfigDict(extra="forbid")

    code: str = Field(description="the code to enter at checkout; matched case-insensitively")
    description: str = ""
    percent_off: float | None = Field(
        default=None, description="e.g. 15 for 15% off; null for a fixed amount"
    )
    amount_off: float | None = Field(default=None, description="e.g. 10.0 for $10 off; null for a percentage")
    min_subtotal: float = Field(default=0, description="the smallest cart subtotal the code applies to")
    expires_at: SimTime | None = Field(default=None, description="valid before this time; null for never")
    active: bool = True

    @model_validator(mode="after")
    def _one_kind_of_discount(self) -> DiscountCode:
        if not self.code.strip() or self.code != self.code.strip():
            raise ValueError(f"discount code {self.code!r} must be non-empty, without surrounding spaces")
        if (self.percent_off is None) == (self.amount_off is None):
            raise ValueError(f"discount code '{self.code}' needs exactly one of percent_off and amount_off")
        if self.percent_off is not None and not 0 < self.percent_off <= 100:
            raise ValueError(f"discount code '{self.code}': percent_off must be above 0 and at most 100")
        if self.amount_off is not None:
            _check_money(self.amount_off, f"discount code '{self.code}': amount_off")
            if self.amount_off == 0:
                raise ValueError(f"discount code '{self.code}': amount_off must be above 0")
        _check_money(self.min_subtotal, f"discount code '{self.code}': min_subtotal")
        return self


class OrderItem(BaseModel):
    """A line of an order, with the names and price as they were when it was placed."""

    model_config = ConfigDict(extra="forbid")

    item_id: str
    product_name: str
    variant_name: str
    quantity: int = Field(ge=1)
    unit_price: float

    @field_validator("unit_price")
    @classmethod
    def _price_in_cents(cls, value: float) -> float:
        return _check_money(value, "unit_price")


class Order(BaseModel):
    """An order the user placed."""

    model_config = ConfigDict(extra="forbid")

    order_id: str
    items: list[OrderItem] = Field(min_length=1)
    subtotal: float
    discount_code: str | None = None
    discount: float = 0
    total: float
    status: OrderStatus = "placed"
    placed_at: SimTime
    updated_at: SimTime = Field(description="when the status last changed; the placing time when left out")

    @model_validator(mode="before")
    @classmethod
    def _updated_when_placed(cls, data: Any) -> Any:
        if isinstance(data, dict) and data.get("updated_at") is None and "placed_at" in data:
            data = {**data, "updated_at": data["placed_at"]}
        return data

    @model_validator(mode="after")
    def _amounts_add_up(self) -> Order:
        for what in ("subtotal", "discount", "total"):
            _check_money(getattr(self, what), f"order '{self.order_id}': {what}")
        lines = sum(_cents(item.unit_price) * item.quantity for item in self.items)
        if lines != _cents(self.subtotal):
            raise ValueError(f"order '{self.order_id}': subtotal {self.subtotal} is not the sum of its items")
        if _cents(self.discount) > _cents(self.subtotal):
            raise ValueError(f"order '{self.order_id}': the discount exceeds the subtotal")
        if _cents(self.total) != _cents(self.subtotal) - _cents(self.discount):
            raise ValueError(f"order '{self.order_id}': total must be subtotal minus discount")
        if self.updated_at < self.placed_at:
            raise ValueError(f"order '{self.order_id}': updated_at is before placed_at")
        return self


class ShoppingState(BaseModel):
    """The store's products and discount codes, the user's cart and orders."""

    model_config = ConfigDict(extra="forbid")

    products: dict[str, Product] = Field(default_factory=dict)
    cart: dict[str, int] = Field(default_factory=dict, description="quantity by item id, in the order added")
    discount_codes: dict[str, DiscountCode] = Field(default_factory=dict)
    orders: dict[str, Order] = Field(default_factory=dict)

    @model_validator(mode="after")
    def _consistent(self) -> ShoppingState:
        items: set[str] = set()
        for key, product in self.products.items():
            if key != product.product_id:
                raise ValueError(f"product stored under '{key}' has product_id '{product.product_id}'")
            for item_id in product.variants:
                if item_id in items:
                    raise ValueError(f"item id '{item_id}' is used by two variants")
                items.add(item_id)
        for item_id, quantity in self.cart.items():
            if item_id not in items:
                raise ValueError(f"the cart holds '{item_id}', which is no product's variant")
            if quantity < 1:
                raise ValueError(f"the cart holds {quantity} of '{item_id}'; quantities start at 1")
        codes: set[str] = set()
        for key, code in self.discount_codes.items():
            if key != code.code:
                raise ValueError(f"discount code stored under '{key}' has code '{code.code}'")
            if key.casefold() in codes:
                raise ValueError(f"discount code '{key}' is there twice (codes ignore case)")
            codes.add(key.casefold())
        for key, order in self.orders.items():
            if key != order.order_id:
                raise ValueError(f"order stored under '{key}' has order_id '{order.order_id}'")
        return self


# -- what the tools return -------------------------------------------------------------------------------


class VariantRow(BaseModel):
    """A variant as a product list shows it: the item id ``add_to_cart`` takes, its name and price."""

    item_id: str
    name: str
    price: float


class ProductSummary(BaseModel):
    """A product as listed: its price range and which of its variants are in stock.

    Availability is per variant: a product whose black model sells and whose silver one is sold out is
    neither simply in stock nor out of it, and the variant the user needs may be the missing one.
    """

    product_id: str
    name: str
    brand: str
    category: str
    description: str
    min_price: float
    max_price: float
    variant_count: int
    in_stock: list[VariantRow] = Field(
        description="the variants in stock, with the item ids add_to_cart takes; [] when none is"
    )
    out_of_stock: list[VariantRow] = Field(description="the variants sold out; [] when none is")


class ProductPage(Paged):
    """One page of products."""

    rows_field = "products"

    products: list[ProductSummary]
    total: int
    offset: int


class ItemDetails(BaseModel):
    """One variant with its product's name, and how many of it are in the cart."""

    item_id: str
    product_id: str
    product_name: str
    brand: str
    variant_name: str
    options: dict[str, str]
    price: float
    stock: int
    in_cart: int = Field(description="how many of it the cart holds")


class CartLine(BaseModel):
    """A line of the cart at the current price."""

    item_id: str
    product_id: str
    product_name: str
    variant_name: str
    unit_price: float
    quantity: int
    line_total: float
    stock: int = Field(description="how many the store has now; checkout needs at least quantity")


class CartContents(BaseModel):
    """The cart: its lines in the order they were added, and their subtotal."""

    lines: list[CartLine]
    item_count: int = Field(description="the number of units in the cart")
    subtotal: float


class DiscountCodeInfo(BaseModel):
    """A discount code and whether it can be used on the cart now."""

    code: str
    description: str
    percent_off: float | None
    amount_off: float | None
    min_subtotal: float
    expires_at: SimTime | None
    active: bool
    usable_now: bool = Field(description="whether checkout would accept it for the current cart")
    problem: str | None = Field(description="why checkout would refuse it now; null when usable")
    discount_on_cart: float = Field(description="what it would take off the current cart; 0 when not usable")


class ItemSpec(BaseModel):
    """A variant of a new product."""

    model_config = ConfigDict(extra="forbid")

    name: str = Field(description='e.g. "Blue / M"')
    price: float = Field(description="the unit price, >= 0, two decimals")
    stock: int = Field(default=0, ge=0, description="how many the store has")
    options: dict[str, str] = Field(default_factory=dict, description='e.g. {"color": "Blue", "size": "M"}')
    item_id: str | None = Field(default=None, description="the id to give it; a new id when left out")


def _by_name(products: Iterable[Product]) -> list[Product]:
    return sorted(products, key=lambda p: (p.name.lower(), p.product_id))


def _variant_row(variant: Variant) -> VariantRow:
    return VariantRow(item_id=variant.item_id, name=variant.name or variant.item_id, price=variant.price)


def _summary(product: Product) -> ProductSummary:
    prices = [v.price for v in product.variants.values()] or [0.0]
    return ProductSummary(
        product_id=product.product_id,
        name=product.name,
        brand=product.brand,
        category=product.category,
        description=product.description,
        min_price=min(prices),
        max_price=max(prices),
        variant_count=len(product.variants),
        in_stock=[_variant_row(v) for v in product.variants.values() if v.stock > 0],
        out_of_stock=[_variant_row(v) for v in product.variants.values() if v.stock == 0],
    )


def _label(product_name: str, variant_name: str) -> str:
    return f"{product_name} ({variant_name})" if variant_name else product_name


def _describe_items(order: Order) -> str:
    units = sum(item.quantity for item in order.items)
    lines = ", ".join(f"{i.quantity} x {_label(i.product_name, i.variant_name)}" for i in order.items)
    return f"{units} item{'s' if units != 1 else ''}, total {_fmt(_cents(order.total))}: {lines}."


def _describe_discount(code: DiscountCode) -> str:
    if code.percent_off is not None:
        what = f"{Decimal(str(code.percent_off)).normalize():f}% off"
    else:
        what = f"{_fmt(_cents(code.amount_off or 0))} off"
    if code.min_subtotal:
        what += f" orders of {_fmt(_cents(code.min_subtotal))} or more"
    else:
        what += " any order"
    if code.expires_at is not None:
        what += f", valid until {code.expires_at:%Y-%m-%d %H:%M} UTC"
    return what


class ShoppingApp(App):
    """An online store."""

    name = "shopping"
    title = "Shopping"
    description = "An online store: products and their variants, the user's cart, discount codes and orders."
    State = ShoppingState
    # an order is undone by cancelling it, and a cancellation by ordering again (at the prices then)
    harm = {
        "add_to_cart": "reversible",
        "remove_from_cart": "reversible",
        "checkout": "costly",
        "cancel_order": "costly",
    }
    state: ShoppingState

    # -- helpers used by screens ---------------------------------------------------------------------
    def records_dated_after(self, now: datetime) -> list[DatedRecord]:
        """See :meth:`App.records_dated_after`."""
        return [
            DatedRecord(
                ("orders", key, "placed_at" if order.placed_at > now else "updated_at"),
                f"order '{order.order_id}' placed or updated "
                f"{max(order.placed_at, order.updated_at):%Y-%m-%d %H:%M}",
            )
            for key, order in self.state.orders.items()
            if max(order.placed_at, order.updated_at) > now
        ]

    def require_product(self, product_id: str) -> Product:
        """Return the product with ``product_id``; raise a :class:`ToolError` naming it otherwise."""
        product = self.state.products.get(product_id)
        if product is None:
            raise ToolError(
                f"No product with id '{product_id}'. Use search_product or list_all_products to find "
                "product ids."
            )
        return product

    def require_item(self, item_id: str) -> tuple[Product, Variant]:
        """Return the variant with ``item_id`` and its product; raise a :class:`ToolError` otherwise."""
        for product in self.state.products.values():
            variant = product.variants.get(item_id)
            if variant is not None:
                return product, variant
        raise ToolError(
            f"No item with id '{item_id}'. Item ids are the ids of product variants; use "
            "get_product_details to see a product's variants."
        )

    def require_order(self, order_id: str) -> Order:
        """Return the order with ``order_id``; raise a :class:`ToolError` naming it otherwise."""
        order = self.state.orders.get(order_id)
        if order is None:
            raise ToolError(f"No order with id '{order_id}'. Use list_orders to find order ids.")
        return order

    def find_code(self, code: str) -> DiscountCode | None:
        """Return the discount code matching ``code`` case-insensitively, if any."""
        wanted = code.strip().casefold()
        return next((c for key, c in self.state.discount_codes.items() if key.casefold() == wanted), None)

    def item_details(self, item_id: str) -> ItemDetails:
        """Return a variant as the Variant screen shows it."""
        product, variant = self.require_item(item_id)
        return ItemDetails(
            item_id=variant.item_id,
            product_id=product.product_id,
            product_name=product.name,
            brand=product.brand,
            variant_name=variant.name,
            options=dict(variant.options),
            price=variant.price,
            stock=variant.stock,
            in_cart=self.state.cart.get(item_id, 0),
        )

    def cart_contents(self) -> CartContents:
        """Return the cart at the current prices."""
        lines = []
        for item_id, quantity in self.state.cart.items():
            product, variant = self.require_item(item_id)
            lines.append(
                CartLine(
                    item_id=item_id,
                    product_id=product.product_id,
                    product_name=product.name,
                    variant_name=variant.name,
                    unit_price=variant.price,
                    quantity=quantity,
                    line_total=_amount(_cents(variant.price) * quantity),
                    stock=variant.stock,
                )
            )
        return CartContents(
            lines=lines,
            item_count=sum(line.quantity for line in lines),
            subtotal=_amount(self._subtotal_cents()),
        )

    def orders_newest_first(self) -> list[Order]:
        """Return every order, the most recently placed first."""
        ordered = sorted(enumerate(self.state.orders.values()), key=lambda p: (p[1].placed_at, p[0]))
        return [order for _, order in reversed(ordered)]

    def _subtotal_cents(self) -> int:
        total = 0
        for item_id, quantity in self.state.cart.items():
            total += _cents(self.require_item(item_id)[1].price) * quantity
        return total

    def _code_problem(self, code: DiscountCode, subtotal_cents: int) -> str | None:
        """Return why checkout would refuse ``code`` for ``subtotal_cents``, or ``None``."""
        if not code.active:
            return f"Discount code '{code.code}' is no longer active."
        if code.expires_at is not None and self.ctx.now() >= code.expires_at:
            return f"Discount code '{code.code}' expired at {code.expires_at:%Y-%m-%d %H:%M} UTC."
        if subtotal_cents < _cents(code.min_subtotal):
            return (
                f"Discount code '{code.code}' needs a subtotal of at least "
                f"{_fmt(_cents(code.min_subtotal))}; the cart's subtotal is {_fmt(subtotal_cents)}."
            )
        return None

    @staticmethod
    def _discount_cents(code: DiscountCode, subtotal_cents: int) -> int:
        """What ``code`` takes off ``subtotal_cents``, never more than the subtotal."""
        if code.percent_off is not None:
            off = _percent_of(subtotal_cents, code.percent_off)
        else:
            off = _cents(code.amount_off or 0)
        return min(off, subtotal_cents)

    def _restock(self, order: Order) -> None:
        """Put a cancelled order's items back in stock."""
        for item in order.items:
            for product in self.state.products.values():
                variant = product.variants.get(item.item_id)
                if variant is not None:
                    variant.stock += item.quantity
                    break

    # -- agent API: the store ------------------------------------------------------------------------
    @tool("read")
    def list_all_products(self, offset: int = 0, limit: int = PAGE) -> ProductPage:
        """List the store's products sorted by name, a page at a time.

        Args:
            offset: how many products to skip.
            limit: how many products to return (1-100).

        Returns:
            the page of products (with price range and which variants are in stock and which sold out)
            and the total number of products.
        """
        if offset < 0 or not 1 <= limit <= 100:
            raise ToolError("offset must be >= 0 and limit between 1 and 100.")
        ordered = _by_name(self.state.products.values())
        page = [_summary(p) for p in ordered[offset : offset + limit]]
        return ProductPage(products=page, total=len(ordered), offset=offset)

    @tool("read")
    def search_product(self, product_name: str) -> list[ProductSummary]:
        """Search products by name, brand, category or description.

        The search is case-insensitive and every word of the query must match. It matches parts of words
        too: "Priya" finds "Priyanka".

        Args:
            product_name: words to look for, e.g. "running shoes" or "acme kettle".

        Returns:
            the matching products, sorted by name, each with its price range and which variants are in
            stock and which sold out.
        """
        words = product_name.lower().split()
        if not words:
            raise ToolError("The search query is empty.")
        found = []
        for product in self.state.products.values():
            haystack = " ".join([product.name, product.brand, product.category, product.description]).lower()
            if all(word in haystack for word in words):
                found.append(product)
        return [_summary(p) for p in _by_name(found)]

    @tool("read")
    def get_product_details(self, product_id: str) -> Product:
        """Get a product's details with all its variants, their item ids, prices and stock.

        Args:
            product_id: the product's id.

        Returns:
            the product and its variants by item id.
        """
        return self.require_product(product_id)

    # -- agent API: the cart -------------------------------------------------------------------------
    @tool("read")
    def list_cart(self) -> CartContents:
        """Show the cart: each line's current unit price, quantity and line total, and the subtotal.

        Returns:
            the cart's lines in the order they were added and their subtotal.
        """
        return self.cart_contents()

    @tool("write")
    def add_to_cart(self, item_id: str, quantity: int = 1) -> CartContents:
        """Add units of a product variant to the cart.

        Args:
            item_id: the variant's item id (see get_product_details).
            quantity: how many to add, at least 1; the cart cannot hold more than the store has.

        Returns:
            the cart as it is now.
        """
        product, variant = self.require_item(item_id)
        if quantity < 1:
            raise ToolError(f"quantity must be at least 1 (got {quantity}).")
        label = _label(product.name, variant.name)
        held = self.state.cart.get(item_id, 0)
        if variant.stock == 0:
            raise ToolError(f"{label} is out of stock.")
        if held + quantity > variant.stock:
            raise ToolError(
                f"Only {variant.stock} of {label} in stock and {held} already in the cart; "
                f"you can add at most {max(variant.stock - held, 0)}."
            )
        self.state.cart[item_id] = held + quantity
        return self.cart_contents()

    @tool("write")
    def remove_from_cart(self, item_id: str, quantity: int = 1) -> CartContents:
        """Take units of an item out of the cart; the line goes when none is left.

        Args:
            item_id: the item id of a line of the cart (see list_cart).
            quantity: how many to remove, at least 1 and at most the quantity in the cart.

        Returns:
            the cart as it is now.
        """
        held = self.state.cart.get(item_id)
        if held is None:
            raise ToolError(f"Item '{item_id}' is not in the cart. Use list_cart to see the cart's lines.")
        if quantity < 1:
            raise ToolError(f"quantity must be at least 1 (got {quantity}).")
        if quantity > held:
            raise ToolError(f"The cart holds only {held} of item '{item_id}'; cannot remove {quantity}.")
        if quantity == held:
            del self.state.cart[item_id]
        else:
            self.state.cart[item_id] = held - quantity
        return self.cart_contents()

    @tool("write")
    def checkout(self, discount_code: str | None = None) -> Order:
        """Buy everything in the cart: places an order at the current prices and empties the cart.

        Args:
            discount_code: a discount code to apply (case-insensitive), or null for none. It must be active,
                not expired, and the cart's subtotal must reach its minimum.

        Returns:
            the new order, with status "placed".
        """
        if not self.state.cart:
            raise ToolError("The cart is empty; add items with add_to_cart before checking out.")
        subtotal = self._subtotal_cents()
        code: DiscountCode | None = None
        if discount_code is not None and discount_code.strip():
            code = self.find_code(discount_code)
            if code is None:
                raise ToolError(
                    f"No discount code '{discount_code.strip()}'. Use get_all_discount_codes to see the "
                    "codes available."
                )
            problem = self._code_problem(code, subtotal)
            if problem is not None:
                raise ToolError(problem)
        short = []
        for item_id, quantity in self.state.cart.items():
            product, variant = self.require_item(item_id)
            if quantity > variant.stock:
                short.append(
                    f"{_label(product.name, variant.name)} ({quantity} in the cart, {variant.stock} in stock)"
                )
        if short:
            raise ToolError(
                f"Not enough stock for: {'; '.join(short)}. Use remove_from_cart to reduce these lines."
            )
        items = []
        for item_id, quantity in self.state.cart.items():
            product, variant = self.require_item(item_id)
            items.append(
                OrderItem(
                    item_id=item_id,
                    product_name=product.name,
                    variant_name=variant.name,
                    quantity=quantity,
                    unit_price=variant.price,
                )
            )
        discount = self._discount_cents(code, subtotal) if code is not None else 0
        now = self.ctx.now()
        order = Order(
            order_id=self.new_id("order", self.state.orders),
            items=items,
            subtotal=_amount(subtotal),
            discount_code=code.code if code is not None else None,
            discount=_amount(discount),
            total=_amount(subtotal - discount),
            status="placed",
            placed_at=now,
            updated_at=now,
        )
        for item in items:
            self.require_item(item.item_id)[1].stock -= item.quantity
        self.state.orders[order.order_id] = order
        self.state.cart.clear()
        return order

    # -- agent API: discount codes -------------------------------------------------------------------
    @tool("read")
    def get_discount_code_info(self, code: str) -> DiscountCodeInfo:
        """Get a discount code's terms and whether checkout would accept it for the current cart.

        Args:
            code: the discount code, in any case, e.g. "spring20".

        Returns:
            the code's terms, whether it is usable now (and if not, why), and what it would take off the
            current cart.
        """
        found = self.find_code(code)
        if found is None:
            raise ToolError(
                f"No discount code '{code.strip()}'. Use get_all_discount_codes to see the codes available."
            )
        subtotal = self._subtotal_cents()
        problem = self._code_problem(found, subtotal)
        if problem is None and not self.state.cart:
            problem = "The cart is empty."
        off = self._discount_cents(found, subtotal) if problem is None else 0
        return DiscountCodeInfo(
            **found.model_dump(),
            usable_now=problem is None,
            problem=problem,
            discount_on_cart=_amount(off),
        )

    @tool("read")
    def get_all_discount_codes(self) -> list[DiscountCode]:
        """List the discount codes that are active and not expired, whatever the cart holds.

        Returns:
            the codes sorted alphabetically, with their terms (percent or amount off, minimum subtotal,
            expiry).
        """
        now = self.ctx.now()
        valid = [
            c
            for c in self.state.discount_codes.values()
            if c.active and (c.expires_at is None or now < c.expires_at)
        ]
        return sorted(valid, key=lambda c: (c.code.casefold(), c.code))

    # -- agent API: orders ---------------------------------------------------------------------------
    @tool("read")
    def list_orders(self) -> list[Order]:
        """List the user's orders, the most recent first.

        Returns:
            every order with its items, amounts and status.
        """
        return self.orders_newest_first()

    @tool("read")
    def get_order_details(self, order_id: str) -> Order:
        """Get one order's items, amounts, discount and status.

        Args:
            order_id: the order's id, e.g. "order-3".

        Returns:
            the order.
        """
        return self.require_order(order_id)

    @tool("write")
    def cancel_order(self, order_id: str) -> Order:
        """Cancel an order that has not shipped yet (status placed or processing).

        Args:
            order_id: the order to cancel.

        Returns:
            the order, now cancelled; its items are back in the store's stock.
        """
        order = self.require_order(order_id)
        if order.status not in _CANCELLABLE:
            raise ToolError(
                f"Order {order_id} is {order.status} and can no longer be cancelled; only placed or "
                "processing orders can."
            )
        self._restock(order)
        order.status = "cancelled"
        order.updated_at = self.ctx.now()
        return order

    # -- the world -----------------------------------------------------------------------------------
    @tool("env", actors=())
    def update_item_price(self, item_id: str, new_price: float) -> Variant:
        """Change a variant's price. If it is in the cart and got cheaper, the user is notified.

        Args:
            item_id: the variant's item id.
            new_price: the new unit price, >= 0, two decimals.

        Returns:
            the variant as it is now.
        """
        product, variant = self.require_item(item_id)
        try:
            _check_money(new_price, "new_price")
        except ValueError as error:
            raise ToolError(f"{error}.") from None
        old = _cents(variant.price)
        new = _cents(new_price)
        variant.price = _amount(new)
        if new < old and item_id in self.state.cart:
            label = _label(product.name, variant.name)
            self.notify(
                "price_drop",
                f"Price drop on {label}",
                subject=f"Now {_fmt(new)}, was {_fmt(old)}",
                body=(
                    f"{label}, which is in your cart, now costs {_fmt(new)} instead of {_fmt(old)}: "
                    f"{_fmt(old - new)} less each."
                ),
                data={
                    "item_id": item_id,
                    "product_id": product.product_id,
                    "old_price": _amount(old),
                    "new_price": _amount(new),
                },
            )
        return variant

    @tool("env", actors=())
    def update_item_stock(self, item_id: str, new_stock: int) -> Variant:
        """Set how many of a variant the store has. If it is in the cart and was out of stock, the user is
        notified that it is back.

        Args:
            item_id: the variant's item id.
            new_stock: how many the store has now, >= 0.

        Returns:
            the variant as it is now.
        """
        product, variant = self.require_item(item_id)
        if new_stock < 0:
            raise ToolError(f"new_stock cannot be negative (got {new_stock}).")
        old = variant.stock
        variant.stock = new_stock
        held = self.state.cart.get(item_id)
        if old == 0 and new_stock > 0 and held is not None:
            label = _label(product.name, variant.name)
            self.notify(
                "back_in_stock",
                f"Back in stock: {label}",
                subject=f"{new_stock} available",
                body=(
                    f"{label}, which is in your cart ({held}), is available again: the store has "
                    f"{new_stock} in stock."
                ),
                data={"item_id": item_id, "product_id": product.product_id, "stock": new_stock},
            )
        return variant

    @tool("env", actors=())
    def add_discount_code(
        self,
        code: str,
        description: str,
        percent_off: float | None = None,
        amount_off: float | None = None,
        min_subtotal: float = 0,
        expires_at: SimTime | None = None,
    ) -> DiscountCode:
        """Offer a new discount code; the user is notified.

        Args:
            code: the code, e.g. "SPRING20"; it must not exist yet (codes ignore case).
            description: what it is for, e.g. "Spring sale".
            percent_off: the percentage off the subtotal, above 0 and at most 100; or give amount_off.
            amount_off: a fixed amount off the subtotal, above 0; or give percent_off.
            min_subtotal: the smallest subtotal the code applies to.
            expires_at: when it stops being valid, ISO 8601 in UTC; null for never.

        Returns:
            the new discount code.
        """
        text = code.strip()
        if not text:
            raise ToolError("The discount code cannot be empty.")
        if self.find_code(text) is not None:
            raise ToolError(f"A discount code '{text}' already exists (codes ignore case); choose another.")
        if expires_at is not None and ensure_utc(expires_at) <= self.ctx.now():
            raise ToolError(f"expires_at ({expires_at:%Y-%m-%d %H:%M}) is not in the future.")
        try:
            new = DiscountCode(
                code=text,
                description=description.strip(),
                percent_off=percent_off,
                amount_off=amount_off,
                min_subtotal=min_subtotal,
                expires_at=expires_at,
            )
        except ValidationError as error:
            problems = "; ".join(str(e["msg"]).removeprefix("Value error, ") for e in error.errors())
            raise ToolError(f"{problems}.") from None
        self.state.discount_codes[text] = new
        self.notify(
            "new_discount_code",
            f"New discount code {text}",
            subject=new.description,
            body=f"{_describe_discount(new)}. Enter {text} at checkout.",
            data={"code": text},
        )
        return new

    @tool("env", actors=())
    def update_order_status(self, order_id: str, status: OrderStatus) -> Order:
        """Move an order forward or cancel it before it ships. The user is notified.

        Orders go placed -> processing -> shipped -> delivered (steps may be skipped); placed or processing
        orders can be cancelled, and a cancelled order's items go back in stock.

        Args:
            order_id: the order.
            status: its new status: processing, shipped, delivered or cancelled.

        Returns:
            the order as it is now.
        """
        order = self.require_order(order_id)
        old = order.status
        if status == old:
            raise ToolError(f"Order {order_id} is already {old}.")
        if status == "cancelled":
            if old not in _CANCELLABLE:
                raise ToolError(
                    f"Order {order_id} is {old}; only placed or processing orders can be cancelled."
                )
        elif old == "cancelled" or _PROGRESS.index(status) < _PROGRESS.index(old):
            raise ToolError(
                f"Order {order_id} cannot go from {old} to {status}; orders move forward only "
                "(placed -> processing -> shipped -> delivered)."
            )
        if status == "cancelled":
            self._restock(order)
        order.status = status
        order.updated_at = self.ctx.now()
        self.notify(
            "order_status",
            f"Your order {order_id} {_STATUS_HEADLINES[status]}",
            body=_describe_items(order),
            data={"order_id": order_id, "status": status, "previous_status": old},
        )
        return order

    @tool("env", actors=())
    def add_product(
        self,
        name: str,
        variants: list[ItemSpec],
        description: str = "",
        category: str = "",
        brand: str = "",
        product_id: str | None = None,
    ) -> Product:
        """Add a product to the store (no notification).

        Args:
            name: the product's name, e.g. "Trail Runner 2".
            variants: its variants, at least one, e.g. [{"name": "Blue / 42", "price": 89.99, "stock": 5,
                "options": {"color": "Blue", "size": "42"}}].
            description: what it is.
            category: e.g. "Shoes".
            brand: e.g. "Acme".
            product_id: the id to give it (scenarios refer to it); a new id when left out.

        Returns:
            the new product with its variants.
        """
        if not name.strip():
            raise ToolError("A product needs a name.")
        if not variants:
            raise ToolError("A product needs at least one variant.")
        if product_id is not None:
            if not product_id.strip():
                raise ToolError("product_id cannot be empty; leave it out to get a new id.")
            if product_id in self.state.products:
                raise ToolError(f"A product with id '{product_id}' already exists; choose another id.")
        taken = {item_id for p in self.state.products.values() for item_id in p.variants}
        chosen: set[str] = set()
        for spec in variants:
            if not spec.name.strip():
                raise ToolError("Every variant needs a name.")
            try:
                _check_money(spec.price, f"price of variant '{spec.name}'")
            except ValueError as error:
                raise ToolError(f"{error}.") from None
            if spec.item_id is not None:
                if not spec.item_id.strip():
                    raise ToolError("A variant's item_id cannot be empty; leave it out to get a new id.")
                if spec.item_id in taken or spec.item_id in chosen:
                    raise ToolError(f"An item with id '{spec.item_id}' already exists; choose another id.")
                chosen.add(spec.item_id)
        new_id = product_id or self.new_id("product", self.state.products)
        items: dict[str, Variant] = {}
        for spec in variants:
            item_id = spec.item_id or self.new_id("item", taken | chosen | set(items))
            items[item_id] = Variant(
                item_id=item_id,
                product_id=new_id,
                name=spec.name.strip(),
                options=dict(spec.options),
                price=spec.price,
                stock=spec.stock,
            )
        product = Product(
            product_id=new_id,
            name=name.strip(),
            description=description.strip(),
            category=category.strip(),
            brand=brand.strip(),
            variants=items,
        )
        self.state.products[new_id] = product
        return product


# -- screens -----------------------------------------------------------------------------------------


def _product_row(summary: ProductSummary) -> dict[str, Any]:
    """A product as the front page lists it: name, brand, price (or range), variants in stock or not."""
    low, high = summary.min_price, summary.max_price
    row: dict[str, Any] = {
        "product_id": summary.product_id,
        "name": summary.name,
        "brand": summary.brand,
        "price": _fmt(_cents(low)) if low == high else f"{_fmt(_cents(low))}-{_fmt(_cents(high))}",
        "in_stock": [variant.model_dump() for variant in summary.in_stock],
    }
    if summary.out_of_stock:
        row["out_of_stock"] = [variant.model_dump() for variant in summary.out_of_stock]
    return row


def _order_row(order: Order) -> dict[str, Any]:
    """An order as a list shows it: id, status, total, when it was placed and what it holds."""
    return {
        "order_id": order.order_id,
        "status": order.status,
        "total": order.total,
        "placed": short_time(order.placed_at),
        "items": "; ".join(f"{i.quantity} x {_label(i.product_name, i.variant_name)}" for i in order.items),
    }


class ShopHome(Screen):
    """The store's front page."""

    name = "Home"
    title = "Shop"

    def display(self, app: ShoppingApp) -> dict[str, Any]:
        """The store's front page: the first products by name (price, which variants are in stock), the
        number of products, what the cart holds, and the latest order's status.
        """
        page = app.list_all_products(limit=PAGE)
        cart = app.cart_contents()
        shown: dict[str, Any] = {
            "total_products": page.total,
            "products": [_product_row(summary) for summary in page.products],
            **showing_screen(page.products, page.total, "list_products(offset={offset})"),
            "cart": {"items": cart.item_count, "subtotal": cart.subtotal},
        }
        orders = app.orders_newest_first()
        if orders:
            shown["latest_order"] = _order_row(orders[0])
        return shown

    @action(kind="read")
    def list_products(self, app: ShoppingApp, offset: int = 0, limit: int = PAGE) -> ProductPage:
        """Show a page of the store's products, sorted by name.

        Args:
            offset: how many products to skip.
            limit: how many to show (1-100).
        """
        return app.list_all_products(offset=offset, limit=limit)

    @action(kind="read")
    def search_products(self, app: ShoppingApp, query: str) -> list[ProductSummary]:
        """Search products by name, brand, category or description. It matches parts of words too: "Priya"
        finds "Priyanka".

        Args:
            query: what to look for, e.g. "running shoes".
        """
        return app.search_product(query)

    @action("Product")
    def view_product(self, app: ShoppingApp, product_id: str) -> Transition:
        """Open a product's page with its variants.

        Args:
            product_id: the product's id.
        """
        return push(ProductScreen(product_id=product_id), app.require_product(product_id))

    @action("Cart")
    def view_cart(self, app: ShoppingApp) -> Transition:
        """Open your cart."""
        return push(CartScreen(), app.cart_contents())

    @action("Orders")
    def list_orders(self, app: ShoppingApp) -> Transition:
        """Open your orders, the most recent first."""
        return push(OrdersScreen(), app.orders_newest_first())


class ProductScreen(Screen):
    """One product's page."""

    name = "Product"
    title = "Product"
    product_id: str

    def display(self, app: ShoppingApp) -> Product | str:
        """The product with every variant (item id, options, price, stock), as view_product shows it."""
        product = app.state.products.get(self.product_id)
        return product if product is not None else f"Product {self.product_id} is no longer sold."

    @action(kind="read")
    def view_product(self, app: ShoppingApp) -> Product:
        """Show this product's details and variants as they are now."""
        return app.require_product(self.product_id)

    @action("Variant")
    def view_variant(self, app: ShoppingApp, item_id: str) -> Transition:
        """Open one of this product's variants (a size, a colour) to buy it.

        Args:
            item_id: the variant's item id, as listed on this page.
        """
        product = app.require_product(self.product_id)
        if item_id not in product.variants:
            listed = ", ".join(f"{v.item_id} ({v.name})" for v in product.variants.values()) or "none"
            raise ToolError(f"'{item_id}' is not a variant of {product.name}; its variants are: {listed}.")
        return push(VariantScreen(item_id=item_id), app.item_details(item_id))


class VariantScreen(Screen):
    """One variant of a product, ready to add to the cart."""

    name = "Variant"
    title = "Product variant"
    item_id: str

    def display(self, app: ShoppingApp) -> ItemDetails | str:
        """The variant's price, stock and how many the cart holds, as view_variant shows it."""
        try:
            return app.item_details(self.item_id)
        except ToolError:
            return f"Item {self.item_id} is no longer sold."

    @action(kind="read")
    def view_variant(self, app: ShoppingApp) -> ItemDetails:
        """Show this variant's price and stock as they are now."""
        return app.item_details(self.item_id)

    @action("Cart", kind="write")
    def add_to_cart(self, app: ShoppingApp, quantity: int = 1) -> Transition:
        """Add this variant to your cart and open the cart.

        Args:
            quantity: how many to add, at least 1.
        """
        return push(CartScreen(), app.add_to_cart(self.item_id, quantity))


class CartScreen(Screen):
    """The user's cart."""

    name = "Cart"
    title = "Cart"

    def display(self, app: ShoppingApp) -> CartContents:
        """The cart at the current prices, as view_cart shows it."""
        return app.cart_contents()

    @action(kind="read")
    def view_cart(self, app: ShoppingApp) -> CartContents:
        """Show what is in your cart, at the current prices, and the subtotal."""
        return app.cart_contents()

    @action(kind="write")
    def remove_item(self, app: ShoppingApp, item_id: str, quantity: int = 1) -> CartContents:
        """Take units of an item out of your cart; the line goes when none is left.

        Args:
            item_id: the item id of a line of the cart.
            quantity: how many to remove, at least 1.
        """
        return app.remove_from_cart(item_id, quantity)

    @action("OrderDetail", kind="write")
    def checkout(self, app: ShoppingApp, discount_code: str | None = None) -> Transition:
        """Buy everything in your cart and open the new order.

        Args:
            discount_code: a discount code to apply, or leave it out for none.
        """
        order = app.checkout(discount_code)
        return replace(OrderDetailScreen(order_id=order.order_id), order)


class OrdersScreen(Screen):
    """The user's orders."""

    name = "Orders"
    title = "Your orders"

    def display(self, app: ShoppingApp) -> dict[str, Any]:
        """The most recent orders (id, status, total, what they hold), with the number of orders."""
        orders = app.orders_newest_first()
        return {
            "total": len(orders),
            "orders": [_order_row(order) for order in orders[:PAGE]],
            **showing_screen(orders[:PAGE], len(orders), "list_orders()"),
        }

    @action(kind="read")
    def list_orders(self, app: ShoppingApp) -> list[Order]:
        """Show your orders, the most recent first."""
        return app.orders_newest_first()

    @action("OrderDetail")
    def view_order(self, app: ShoppingApp, order_id: str) -> Transition:
        """Open an order's page.

        Args:
            order_id: the order's id.
        """
        return push(OrderDetailScreen(order_id=order_id), app.require_order(order_id))


class OrderDetailScreen(Screen):
    """One order's page."""

    name = "OrderDetail"
    title = "Order details"
    order_id: str

    def display(self, app: ShoppingApp) -> Order | str:
        """The order in full (items, amounts, status), as view_order shows it."""
        order = app.state.orders.get(self.order_id)
        return order if order is not None else f"Order {self.order_id} no longer exists."

    @action(kind="read")
    def view_order(self, app: ShoppingApp) -> Order:
        """Show this order's items, amounts and status as they are now."""
        return app.require_order(self.order_id)

    @action(kind="write")
    def cancel_order(self, app: ShoppingApp) -> Order:
        """Cancel this order, if it has not shipped yet."""
        return app.cancel_order(self.order_id)


ShoppingApp.set_screens(ShopHome, ProductScreen, VariantScreen, CartScreen, OrdersScreen, OrderDetailScreen)
