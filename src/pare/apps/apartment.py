"""Apartments: rental listings the user browses, searches and saves."""

from __future__ import annotations

import re
from collections.abc import Iterable
from datetime import datetime
from enum import StrEnum
from typing import Any

from pydantic import BaseModel, ConfigDict, Field, ValidationError, model_validator

from pare.apps.base import App
from pare.apps.paging import Paged, showing_screen
from pare.apps.screens import Screen, Transition, action, push
from pare.apps.text import PAGE, optional_text, unique_names
from pare.apps.tools import tool
from pare.apps.types import SimTime
from pare.errors import ToolError


def _key(text: str) -> str:
    """``text`` reduced to lowercase letters and digits, for forgiving comparisons."""
    return re.sub(r"[^a-z0-9]", "", text.lower())


class _Choice(StrEnum):
    """A fixed set of values that accepts any spelling of one (case, spaces, hyphens) and a few aliases."""

    @classmethod
    def _aliases(cls) -> dict[str, str]:
        return {}

    @classmethod
    def _missing_(cls, value: object) -> _Choice | None:
        if not isinstance(value, str):
            return None
        wanted = _key(value)
        for member in cls:
            if _key(member.value) == wanted:
                return member
        alias = {_key(a): v for a, v in cls._aliases().items()}.get(wanted)
        return None if alias is None else cls(alias)


class PropertyType(_Choice):
    """The kind of property: Apartment, Condo, House, Townhouse or Studio (any case)."""

    APARTMENT = "Apartment"
    CONDO = "Condo"
    HOUSE = "House"
    TOWNHOUSE = "Townhouse"
    STUDIO = "Studio"


class FurnishedStatus(_Choice):
    """Whether it comes furnished: Furnished, Unfurnished or Semi-furnished (any case)."""

    FURNISHED = "Furnished"
    UNFURNISHED = "Unfurnished"
    SEMI_FURNISHED = "Semi-furnished"


class FloorLevel(_Choice):
    """Where in the building it is, as a category rather than a floor number (listings rarely give one):
    Basement, Ground, Upper (any floor above the ground one) or Penthouse (any case).
    """

    BASEMENT = "Basement"
    GROUND = "Ground"
    UPPER = "Upper"
    PENTHOUSE = "Penthouse"

    @classmethod
    def _aliases(cls) -> dict[str, str]:
        return {"Ground floor": "Ground", "Upper floor": "Upper", "Upper floors": "Upper"}


class PetPolicy(_Choice):
    """Which pets the landlord accepts: Pets allowed, Cats allowed, Dogs allowed or No pets (any case)."""

    PETS_ALLOWED = "Pets allowed"
    CATS_ALLOWED = "Cats allowed"
    DOGS_ALLOWED = "Dogs allowed"
    NO_PETS = "No pets"

    @classmethod
    def _aliases(cls) -> dict[str, str]:
        return {"No pets allowed": "No pets", "Pet friendly": "Pets allowed"}


class LeaseTerm(_Choice):
    """The length of the lease: Month-to-month, 6 months, 1 year or Long term (any case)."""

    MONTH_TO_MONTH = "Month-to-month"
    SIX_MONTHS = "6 months"
    ONE_YEAR = "1 year"
    LONG_TERM = "Long term"

    @classmethod
    def _aliases(cls) -> dict[str, str]:
        return {"12 months": "1 year", "Monthly": "Month-to-month"}


class Apartment(BaseModel):
    """A rental listing."""

    model_config = ConfigDict(extra="forbid")

    apartment_id: str
    name: str = Field(description="the listing's title, e.g. 'Sunny 2BR near Dolores Park'")
    location: str = Field(description="the neighbourhood or city, e.g. 'Mission District, San Francisco'")
    address: str
    price: float = Field(ge=0, description="monthly rent in dollars")
    bedrooms: int = Field(ge=0, description="0 for a studio")
    bathrooms: float = Field(ge=0, description="e.g. 1.5 for one full and one half bathroom")
    property_type: PropertyType = PropertyType.APARTMENT
    square_footage: int | None = Field(default=None, gt=0)
    furnished_status: FurnishedStatus | None = None
    floor_level: FloorLevel | None = Field(default=None, description="Basement, Ground, Upper or Penthouse")
    pet_policy: PetPolicy | None = None
    lease_term: LeaseTerm | None = None
    amenities: list[str] = Field(default_factory=list, description="e.g. Gym, Parking, In-unit laundry")
    available_from: SimTime | None = Field(default=None, description="when the tenancy can start")
    description: str | None = None

    @model_validator(mode="after")
    def _has_name_and_place(self) -> Apartment:
        for field in ("name", "location", "address"):
            if not getattr(self, field).strip():
                raise ValueError(f"apartment '{self.apartment_id}' has an empty {field}")
        return self


class ApartmentDetails(Apartment):
    """A listing with whether the user saved it."""

    saved: bool = Field(description="whether the listing is in the user's saved apartments")


class ApartmentUpdate(BaseModel):
    """Fields to change on a listing; fields left out are kept, null removes an optional field."""

    model_config = ConfigDict(extra="forbid")

    name: str | None = None
    location: str | None = None
    address: str | None = None
    price: float | None = Field(default=None, ge=0)
    bedrooms: int | None = Field(default=None, ge=0)
    bathrooms: float | None = Field(default=None, ge=0)
    property_type: PropertyType | None = None
    square_footage: int | None = Field(default=None, gt=0)
    furnished_status: FurnishedStatus | None = None
    floor_level: FloorLevel | None = None
    pet_policy: PetPolicy | None = None
    lease_term: LeaseTerm | None = None
    amenities: list[str] | None = None
    available_from: SimTime | None = None
    description: str | None = None


_REQUIRED = ("name", "location", "address", "price", "bedrooms", "bathrooms", "property_type")
_TEXTS = ("name", "location", "address")


class ApartmentState(BaseModel):
    """Every listing by id, and the ids the user saved, in the order they were saved."""

    model_config = ConfigDict(extra="forbid")

    apartments: dict[str, Apartment] = Field(default_factory=dict)
    saved: list[str] = Field(default_factory=list, description="ids of saved listings, oldest first")

    @model_validator(mode="after")
    def _consistent(self) -> ApartmentState:
        for key, apartment in self.apartments.items():
            if key != apartment.apartment_id:
                raise ValueError(
                    f"apartment stored under '{key}' has apartment_id '{apartment.apartment_id}'"
                )
        if len(set(self.saved)) != len(self.saved):
            raise ValueError("saved lists an apartment more than once")
        missing = [apartment_id for apartment_id in self.saved if apartment_id not in self.apartments]
        if missing:
            raise ValueError(f"saved refers to unknown apartment(s) {', '.join(missing)}")
        return self


class ApartmentPage(Paged):
    """One page of listings."""

    rows_field = "apartments"

    apartments: list[Apartment]
    total: int
    offset: int


def money(amount: float) -> str:
    """Format a rent for people, e.g. ``$2,950`` or ``$1,899.50``."""
    return f"${amount:,.0f}" if amount == int(amount) else f"${amount:,.2f}"


def _show(field: str, value: Any) -> str:
    """One field's value as a change description shows it."""
    if value is None or value == []:
        return "none"
    if field == "price":
        return money(value)
    if isinstance(value, datetime):
        return f"{value:%Y-%m-%d}"
    if isinstance(value, list):
        return ", ".join(str(item) for item in value)
    return str(value)


def _describe_change(field: str, old: Any, new: Any) -> str:
    """A change for people, e.g. ``lease term: 1 year -> 6 months``."""
    label = "rent" if field == "price" else field.replace("_", " ")
    if field == "description":
        return "new description"
    return f"{label}: {_show(field, old)} -> {_show(field, new)}"


def _page(offset: int, limit: int) -> None:
    if offset < 0 or not 1 <= limit <= 100:
        raise ToolError("offset must be >= 0 and limit between 1 and 100.")


def _check_range(what: str, low: float | None, high: float | None) -> None:
    """Raise a :class:`ToolError` for a negative bound or a minimum above the maximum."""
    for bound, value in (("min", low), ("max", high)):
        if value is not None and value < 0:
            raise ToolError(f"{bound}_{what} cannot be negative (got {value}).")
    if low is not None and high is not None and low > high:
        raise ToolError(f"min_{what} ({low}) is above max_{what} ({high}); swap them or drop one.")


def _by_price(apartments: Iterable[Apartment]) -> list[Apartment]:
    return sorted(apartments, key=lambda a: (a.price, a.apartment_id))


class ApartmentApp(App):
    """Rental listings."""

    name = "apartment"
    title = "Apartments"
    description = "Rental listings: browse and search apartments, and keep a list of saved ones."
    State = ApartmentState
    harm = {
        "save_apartment": "reversible",
        "remove_saved_apartment": "reversible",
    }
    state: ApartmentState

    # -- helpers used by screens ---------------------------------------------------------------------
    def require(self, apartment_id: str) -> Apartment:
        """Return the listing with ``apartment_id``; raise a :class:`ToolError` naming it otherwise."""
        apartment = self.state.apartments.get(apartment_id)
        if apartment is None:
            raise ToolError(
                f"No apartment with id '{apartment_id}'. Use list_all_apartments or search_apartments to "
                "find apartment ids."
            )
        return apartment

    def details(self, apartment_id: str) -> ApartmentDetails:
        """Return the listing with whether it is saved."""
        apartment = self.require(apartment_id)
        return ApartmentDetails.model_validate(
            {**apartment.model_dump(), "saved": apartment_id in self.state.saved}
        )

    # -- agent API -----------------------------------------------------------------------------------
    @tool("read")
    def list_all_apartments(self, offset: int = 0, limit: int = PAGE) -> ApartmentPage:
        """List every apartment listing, sorted by name, a page at a time.

        Args:
            offset: how many listings to skip.
            limit: how many listings to return (1-100).

        Returns:
            the page of listings and the total number of listings.
        """
        _page(offset, limit)
        ordered = sorted(self.state.apartments.values(), key=lambda a: (a.name.lower(), a.apartment_id))
        return ApartmentPage(apartments=ordered[offset : offset + limit], total=len(ordered), offset=offset)

    @tool("read")
    def get_apartment_details(self, apartment_id: str) -> ApartmentDetails:
        """Get everything about one listing, including whether the user saved it.

        Args:
            apartment_id: the listing's id.

        Returns:
            the listing and its saved flag.
        """
        return self.details(apartment_id)

    @tool("read")
    def search_apartments(
        self,
        location: str | None = None,
        min_price: float | None = None,
        max_price: float | None = None,
        min_bedrooms: int | None = None,
        max_bedrooms: int | None = None,
        min_bathrooms: float | None = None,
        property_type: PropertyType | None = None,
        furnished_status: FurnishedStatus | None = None,
        pet_policy: PetPolicy | None = None,
        lease_term: LeaseTerm | None = None,
        amenities: list[str] | None = None,
        floor_level: FloorLevel | None = None,
        min_square_footage: int | None = None,
        max_square_footage: int | None = None,
        offset: int = 0,
        limit: int = PAGE,
    ) -> ApartmentPage:
        """Search listings; every filter given must match. Results are sorted by price, cheapest first.

        A listing that does not state a filtered attribute (no square footage, no pet policy) does not
        match a filter on it.

        Args:
            location: part of the neighbourhood, city or street address, case-insensitive, e.g. "mission";
                it matches parts of words too: "park" finds "Parkside".
            min_price: lowest monthly rent in dollars.
            max_price: highest monthly rent in dollars.
            min_bedrooms: fewest bedrooms (0 is a studio).
            max_bedrooms: most bedrooms.
            min_bathrooms: fewest bathrooms, e.g. 1.5.
            property_type: one of Apartment, Condo, House, Townhouse, Studio.
            furnished_status: one of Furnished, Unfurnished, Semi-furnished.
            pet_policy: the exact policy, one of Pets allowed, Cats allowed, Dogs allowed, No pets.
            lease_term: one of Month-to-month, 6 months, 1 year, Long term.
            amenities: amenities the listing must all have, names matched exactly but case-insensitively,
                e.g. ["Gym", "Parking"].
            floor_level: one of Basement, Ground, Upper, Penthouse.
            min_square_footage: smallest size in square feet.
            max_square_footage: largest size in square feet.
            offset: how many results to skip.
            limit: how many results to return (1-100).

        Returns:
            the page of matching listings and the total number of matches.
        """
        _page(offset, limit)
        _check_range("price", min_price, max_price)
        _check_range("bedrooms", min_bedrooms, max_bedrooms)
        _check_range("bathrooms", min_bathrooms, None)
        _check_range("square_footage", min_square_footage, max_square_footage)
        place = None
        if location is not None:
            place = location.strip().lower()
            if not place:
                raise ToolError("location is empty; leave it out to search every location.")
        wanted: list[str] = []
        if amenities is not None:
            wanted = [name.casefold() for name in unique_names(amenities)]
            if not wanted:
                raise ToolError("amenities lists no amenity name; leave it out to accept any amenities.")

        def matches(a: Apartment) -> bool:
            size = a.square_footage
            has = {name.casefold() for name in a.amenities}
            return (
                (place is None or place in a.location.lower() or place in a.address.lower())
                and (min_price is None or a.price >= min_price)
                and (max_price is None or a.price <= max_price)
                and (min_bedrooms is None or a.bedrooms >= min_bedrooms)
                and (max_bedrooms is None or a.bedrooms <= max_bedrooms)
                and (min_bathrooms is None or a.bathrooms >= min_bathrooms)
                and (property_type is None or a.property_type == property_type)
                and (furnished_status is None or a.furnished_status == furnished_status)
                and (pet_policy is None or a.pet_policy == pet_policy)
                and (lease_term is None or a.lease_term == lease_term)
                and all(name in has for name in wanted)
                and (floor_level is None or a.floor_level == floor_level)
                and (min_square_footage is None or (size is not None and size >= min_square_footage))
                and (max_square_footage is None or (size is not None and size <= max_square_footage))
            )

        found = _by_price(a for a in self.state.apartments.values() if matches(a))
        return ApartmentPage(apartments=found[offset : offset + limit], total=len(found), offset=offset)

    @tool("read")
    def list_saved_apartments(self) -> list[Apartment]:
        """List the apartments the user saved, in the order they were saved (oldest first).

        Returns:
            the saved listings.
        """
        return [self.state.apartments[apartment_id] for apartment_id in self.state.saved]

    @tool("write")
    def save_apartment(self, apartment_id: str) -> str:
        """Add a listing to the user's saved apartments.

        Args:
            apartment_id: the listing to save.

        Returns:
            confirmation.
        """
        apartment = self.require(apartment_id)
        if apartment_id in self.state.saved:
            raise ToolError(f"Apartment {apartment_id} ({apartment.name}) is already saved.")
        self.state.saved.append(apartment_id)
        return f"Saved apartment {apartment_id} ({apartment.name})."

    @tool("write")
    def remove_saved_apartment(self, apartment_id: str) -> str:
        """Remove a listing from the user's saved apartments; the listing itself stays.

        Args:
            apartment_id: the saved listing to remove; list_saved_apartments shows them.

        Returns:
            confirmation.
        """
        apartment = self.require(apartment_id)
        if apartment_id not in self.state.saved:
            raise ToolError(
                f"Apartment {apartment_id} ({apartment.name}) is not in the saved apartments. "
                "Use list_saved_apartments to see them."
            )
        self.state.saved.remove(apartment_id)
        return f"Removed apartment {apartment_id} ({apartment.name}) from the saved apartments."

    # -- the world -----------------------------------------------------------------------------------
    @tool("env", actors=())
    def add_new_apartment(
        self,
        name: str,
        location: str,
        address: str,
        price: float,
        bedrooms: int,
        bathrooms: float,
        property_type: PropertyType | None = None,
        square_footage: int | None = None,
        furnished_status: FurnishedStatus | None = None,
        floor_level: FloorLevel | None = None,
        pet_policy: PetPolicy | None = None,
        lease_term: LeaseTerm | None = None,
        amenities: list[str] | None = None,
        available_from: datetime | None = None,
        description: str | None = None,
        apartment_id: str | None = None,
    ) -> str:
        """Publish a new listing. It appears silently, without a notification.

        Args:
            name: the listing's title, e.g. "Sunny 2BR near Dolores Park".
            location: the neighbourhood or city, e.g. "Mission District, San Francisco".
            address: the street address.
            price: monthly rent in dollars (>= 0).
            bedrooms: number of bedrooms (0 for a studio).
            bathrooms: number of bathrooms, e.g. 1.5.
            property_type: one of Apartment, Condo, House, Townhouse, Studio; Apartment when left out.
            square_footage: size in square feet.
            furnished_status: one of Furnished, Unfurnished, Semi-furnished.
            floor_level: one of Basement, Ground, Upper, Penthouse.
            pet_policy: one of Pets allowed, Cats allowed, Dogs allowed, No pets.
            lease_term: one of Month-to-month, 6 months, 1 year, Long term.
            amenities: amenity names, e.g. ["Gym", "Parking"].
            available_from: when the tenancy can start, ISO 8601 in UTC, e.g. "2025-04-01".
            description: the listing's text.
            apartment_id: the id to give the listing (scenarios refer to it); a new id when left out.

        Returns:
            the listing's id.
        """
        texts = {"name": name.strip(), "location": location.strip(), "address": address.strip()}
        for field, value in texts.items():
            if not value:
                raise ToolError(f"A listing needs a {field}.")
        for field, number in (("price", price), ("bedrooms", bedrooms), ("bathrooms", bathrooms)):
            if number < 0:
                raise ToolError(f"{field} cannot be negative (got {number}).")
        if square_footage is not None and square_footage <= 0:
            raise ToolError(f"square_footage must be positive (got {square_footage}).")
        if apartment_id is not None:
            if not apartment_id.strip():
                raise ToolError("apartment_id cannot be empty; leave it out to get a new id.")
            if apartment_id in self.state.apartments:
                raise ToolError(f"An apartment with id '{apartment_id}' already exists; choose another id.")
        new_id = apartment_id or self.new_id("apt", self.state.apartments)
        self.state.apartments[new_id] = Apartment(
            apartment_id=new_id,
            **texts,
            price=price,
            bedrooms=bedrooms,
            bathrooms=bathrooms,
            property_type=property_type or PropertyType.APARTMENT,
            square_footage=square_footage,
            furnished_status=furnished_status,
            floor_level=floor_level,
            pet_policy=pet_policy,
            lease_term=lease_term,
            amenities=unique_names(amenities or []),
            available_from=available_from,
            description=optional_text(description),
        )
        return new_id

    @tool("env", actors=())
    def update_apartment(self, apartment_id: str, updates: ApartmentUpdate) -> Apartment:
        """Change a listing (the landlord edits it); fields not given are kept.

        When the listing is one the user saved, both the user and the assistant are notified: a
        "price_drop" when the rent went down, a "listing_updated" for any other change.

        Args:
            apartment_id: the listing to change.
            updates: the fields to change, e.g. {"price": 2850, "lease_term": "6 months"}. Null removes an
                optional field (square footage, furnished status, floor level, pet policy, lease term,
                available from, description); amenities replace the whole list, null or [] clears it.

        Returns:
            the listing as it is now.
        """
        old = self.require(apartment_id)
        changes = updates.model_dump(exclude_unset=True)
        if not changes:
            raise ToolError("No field to change was given.")
        for required in _REQUIRED:
            if required in changes and changes[required] is None:
                raise ToolError(
                    f"A listing's {required} cannot be removed; give a new value or leave it out."
                )
        for field in _TEXTS:
            if field in changes:
                changes[field] = changes[field].strip()
                if not changes[field]:
                    raise ToolError(f"A listing's {field} cannot be empty.")
        if "description" in changes:
            changes["description"] = optional_text(changes["description"])
        if "amenities" in changes:
            changes["amenities"] = unique_names(changes["amenities"] or [])
        try:
            new = Apartment.model_validate({**old.model_dump(), **changes})
        except ValidationError as error:
            raise ToolError(
                f"The update would make the listing invalid: {error.errors()[0]['msg']}."
            ) from None
        self.state.apartments[apartment_id] = new
        changed = [field for field in Apartment.model_fields if getattr(old, field) != getattr(new, field)]
        if changed and apartment_id in self.state.saved:
            self._announce_update(old, new, changed)
        return new

    @tool("env", actors=())
    def delete_apartment(self, apartment_id: str) -> str:
        """Take a listing down (rented or withdrawn); it also leaves the saved apartments.

        When the user had saved it, both the user and the assistant are notified ("listing_removed").

        Args:
            apartment_id: the listing to remove.

        Returns:
            confirmation.
        """
        apartment = self.require(apartment_id)
        was_saved = apartment_id in self.state.saved
        del self.state.apartments[apartment_id]
        if was_saved:
            self.state.saved.remove(apartment_id)
            self.notify(
                "listing_removed",
                "A saved apartment is no longer listed",
                subject=apartment.name,
                body=(
                    "Taken off the market and removed from your saved apartments. It was "
                    f"{money(apartment.price)} a month at {apartment.address}."
                ),
                data={"apartment_id": apartment_id},
            )
        return f"Deleted apartment {apartment_id} ({apartment.name})."

    def _announce_update(self, old: Apartment, new: Apartment, changed: list[str]) -> None:
        """Notify about a change to a saved listing."""
        data: dict[str, Any] = {"apartment_id": new.apartment_id}
        if "price" in changed and new.price < old.price:
            others = [field.replace("_", " ") for field in changed if field != "price"]
            body = f"Now {money(new.price)} a month, down from {money(old.price)}."
            if others:
                body += f" Also changed: {', '.join(others)}."
            body += f" Address: {new.address}."
            data.update(old_price=old.price, new_price=new.price)
            self.notify(
                "price_drop", "Price drop on a saved apartment", subject=new.name, body=body, data=data
            )
            return
        details = "; ".join(
            _describe_change(field, getattr(old, field), getattr(new, field)) for field in changed
        )
        self.notify(
            "listing_updated",
            "A saved apartment was updated",
            subject=new.name,
            body=f"Changed: {details}. Address: {new.address}.",
            data=data,
        )


# -- screens -----------------------------------------------------------------------------------------


def _row(app: ApartmentApp, apartment: Apartment) -> dict[str, Any]:
    """A listing as a list shows it: its name and place, rent, rooms and whether the user saved it."""
    return {
        "apartment_id": apartment.apartment_id,
        "name": apartment.name,
        "location": apartment.location,
        "rent": money(apartment.price),
        "bedrooms": apartment.bedrooms,
        "bathrooms": apartment.bathrooms,
        "saved": apartment.apartment_id in app.state.saved,
    }


class ListingsHome(Screen):
    """Every listing, with the way to search and to the saved ones."""

    name = "Home"
    title = "Apartment listings"

    def display(self, app: ApartmentApp) -> dict[str, Any]:
        """The first listings by name, as list_apartments orders them (rent, rooms, whether saved), with
        the number of listings and of saved ones.
        """
        page = app.list_all_apartments(limit=PAGE)
        return {
            "total": page.total,
            "saved": len(app.state.saved),
            "listings": [_row(app, apartment) for apartment in page.apartments],
            **showing_screen(page.apartments, page.total, "list_apartments(offset={offset})"),
        }

    @action(kind="read")
    def list_apartments(self, app: ApartmentApp, offset: int = 0, limit: int = PAGE) -> ApartmentPage:
        """Show a page of listings, sorted by name.

        Args:
            offset: how many listings to skip.
            limit: how many to show (1-100).
        """
        return app.list_all_apartments(offset=offset, limit=limit)

    @action("Detail")
    def view_apartment(self, app: ApartmentApp, apartment_id: str) -> Transition:
        """Open a listing's page.

        Args:
            apartment_id: the listing's id.
        """
        return push(ListingDetail(apartment_id=apartment_id), app.details(apartment_id))

    @action("Search")
    def open_search(self, app: ApartmentApp) -> Transition:
        """Open the search, to filter listings by location, price, size, amenities and more."""
        count = len(app.state.apartments)
        return push(SearchListings(), f"Search {count} listings; every filter you give must match.")

    @action("Saved")
    def open_favorites(self, app: ApartmentApp) -> Transition:
        """Open your saved apartments."""
        return push(SavedListings(), app.list_saved_apartments())


class SearchListings(Screen):
    """Searching listings with filters."""

    name = "Search"
    title = "Search apartments"

    def display(self, app: ApartmentApp) -> dict[str, Any]:
        """An empty search form: how many listings there are to search (the filters are the search's)."""
        return {"listings": len(app.state.apartments), "filters": "none yet: every filter given must match"}

    @action(kind="read")
    def search(
        self,
        app: ApartmentApp,
        location: str | None = None,
        min_price: float | None = None,
        max_price: float | None = None,
        min_bedrooms: int | None = None,
        max_bedrooms: int | None = None,
        min_bathrooms: float | None = None,
        property_type: PropertyType | None = None,
        furnished_status: FurnishedStatus | None = None,
        pet_policy: PetPolicy | None = None,
        lease_term: LeaseTerm | None = None,
        amenities: list[str] | None = None,
        floor_level: FloorLevel | None = None,
        min_square_footage: int | None = None,
        max_square_footage: int | None = None,
        offset: int = 0,
        limit: int = PAGE,
    ) -> ApartmentPage:
        """Show the listings matching every filter given, cheapest first.

        Args:
            location: part of the neighbourhood, city or street address, e.g. "mission"; it matches parts
                of words too: "park" finds "Parkside".
            min_price: lowest monthly rent in dollars.
            max_price: highest monthly rent in dollars.
            min_bedrooms: fewest bedrooms (0 is a studio).
            max_bedrooms: most bedrooms.
            min_bathrooms: fewest bathrooms.
            property_type: Apartment, Condo, House, Townhouse or Studio.
            furnished_status: Furnished, Unfurnished or Semi-furnished.
            pet_policy: Pets allowed, Cats allowed, Dogs allowed or No pets.
            lease_term: Month-to-month, 6 months, 1 year or Long term.
            amenities: amenities it must all have, e.g. ["Gym", "Parking"].
            floor_level: Basement, Ground, Upper or Penthouse.
            min_square_footage: smallest size in square feet.
            max_square_footage: largest size in square feet.
            offset: how many results to skip.
            limit: how many to show (1-100).
        """
        return app.search_apartments(
            location=location,
            min_price=min_price,
            max_price=max_price,
            min_bedrooms=min_bedrooms,
            max_bedrooms=max_bedrooms,
            min_bathrooms=min_bathrooms,
            property_type=property_type,
            furnished_status=furnished_status,
            pet_policy=pet_policy,
            lease_term=lease_term,
            amenities=amenities,
            floor_level=floor_level,
            min_square_footage=min_square_footage,
            max_square_footage=max_square_footage,
            offset=offset,
            limit=limit,
        )

    @action("Detail")
    def view_apartment(self, app: ApartmentApp, apartment_id: str) -> Transition:
        """Open a listing's page.

        Args:
            apartment_id: the listing's id, from the search results.
        """
        return push(ListingDetail(apartment_id=apartment_id), app.details(apartment_id))


class SavedListings(Screen):
    """The apartments the user saved."""

    name = "Saved"
    title = "Saved apartments"

    def display(self, app: ApartmentApp) -> dict[str, Any]:
        """The first saved listings, oldest saved first as list_saved orders them, with their number."""
        saved = app.list_saved_apartments()
        return {
            "total": len(saved),
            "listings": [_row(app, apartment) for apartment in saved[:PAGE]],
            **showing_screen(saved[:PAGE], len(saved), "list_saved()"),
        }

    @action(kind="read")
    def list_saved(self, app: ApartmentApp) -> list[Apartment]:
        """Show your saved apartments, oldest saved first."""
        return app.list_saved_apartments()

    @action("Detail")
    def view_apartment(self, app: ApartmentApp, apartment_id: str) -> Transition:
        """Open a listing's page; usually a saved one, but any listing's id opens.

        Args:
            apartment_id: the listing's id.
        """
        return push(ListingDetail(apartment_id=apartment_id), app.details(apartment_id))


class ListingDetail(Screen):
    """One listing's page."""

    name = "Detail"
    title = "Apartment details"
    apartment_id: str

    def display(self, app: ApartmentApp) -> ApartmentDetails | str:
        """The listing in full with whether it is saved, as view_apartment shows it (or a line saying it
        was taken down).
        """
        if self.apartment_id not in app.state.apartments:
            return f"Apartment {self.apartment_id} is no longer listed."
        return app.details(self.apartment_id)

    @action(kind="read")
    def view_details(self, app: ApartmentApp) -> ApartmentDetails:
        """Show this listing as it is now, and whether you saved it."""
        return app.details(self.apartment_id)

    @action(kind="write")
    def save(self, app: ApartmentApp) -> str:
        """Add this listing to your saved apartments."""
        return app.save_apartment(self.apartment_id)

    @action(kind="write")
    def unsave(self, app: ApartmentApp) -> str:
        """Remove this listing from your saved apartments."""
        return app.remove_saved_apartment(self.apartment_id)


ApartmentApp.set_screens(ListingsHome, SearchListings, SavedListings, ListingDetail)
