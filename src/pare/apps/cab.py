"""Cab: quotes and rides from a ride-hailing service.

Prices are deterministic. The distance between two places is a pure function of the pair (the same in
both directions): a scenario's ``known_distances`` when it names the pair, however its places are written
(case, punctuation and common abbreviations aside; a name holding all the words of a known place, or held
by it, is that place), otherwise a stable hash of the two names mapped to 1.5-35 km. Rides go at 30 km/h,
so the duration is ``distance / 30 * 60`` minutes rounded up. The price is ``base_fare + per_km *
distance + per_minute * duration`` of the service type, times 1.25 for pickups in the peak hours
(07:00-09:59 and 16:00-18:59), rounded to cents. The same request always gives the same numbers.
"""

from __future__ import annotations

import hashlib
import json
import re
from datetime import datetime, timedelta
from decimal import ROUND_HALF_UP, Decimal
from typing import Any, Literal

from pydantic import BaseModel, ConfigDict, Field, model_validator

from pare.apps.base import App, DatedRecord
from pare.apps.paging import Paged, showing_screen
from pare.apps.screens import Screen, Transition, action, back_to, push, replace
from pare.apps.text import PAGE, short_time
from pare.apps.tools import tool
from pare.apps.types import SimTime
from pare.errors import ToolError
from pare.sim.clock import ensure_utc

RideStatus = Literal[
    "booked",
    "driver_assigned",
    "arriving",
    "in_progress",
    "completed",
    "cancelled_by_user",
    "cancelled_by_driver",
]
ProgressStatus = Literal["driver_assigned", "arriving", "in_progress"]

ACTIVE_STATUSES: tuple[RideStatus, ...] = ("booked", "driver_assigned", "arriving", "in_progress")
"""Statuses of a ride that has not ended, in the order a ride goes through them."""
USER_CANCELLABLE: tuple[RideStatus, ...] = ("booked", "driver_assigned", "arriving")

MIN_DISTANCE_TENTHS = 15
MAX_DISTANCE_TENTHS = 350
SPEED_KMH = 30
PEAK_HOURS = frozenset({7, 8, 9, 16, 17, 18})
PEAK_MULTIPLIER = Decimal("1.25")
QUOTE_GRACE = timedelta(minutes=15)
NO_RIDE_UNDER_WAY = "No ride is under way (none is booked). get_ride_history lists past rides."
"""What the current ride's status reads when there is none: a normal state, so a result and not an error."""
"""How long after its pickup time a quotation can still be ordered."""


class ServiceType(BaseModel):
    """A kind of ride and its fares."""

    model_config = ConfigDict(extra="forbid")

    base_fare: float = Field(ge=0, description="charged for every ride")
    per_km: float = Field(ge=0, description="charged per kilometre")
    per_minute: float = Field(ge=0, description="charged per minute of driving")
    max_passengers: int = Field(ge=1)
    description: str = ""


def default_service_types() -> dict[str, ServiceType]:
    """The service types a cab app offers when a scenario does not choose its own."""
    return {
        "Default": ServiceType(
            base_fare=3.0,
            per_km=1.1,
            per_minute=0.25,
            max_passengers=4,
            description="A standard car for up to 4 passengers.",
        ),
        "Premium": ServiceType(
            base_fare=6.0,
            per_km=1.9,
            per_minute=0.45,
            max_passengers=4,
            description="A high-end car with a top-rated driver, for up to 4 passengers.",
        ),
        "Van": ServiceType(
            base_fare=5.0,
            per_km=1.5,
            per_minute=0.35,
            max_passengers=7,
            description="A van for up to 7 passengers or bulky luggage.",
        ),
        "Pool": ServiceType(
            base_fare=2.0,
            per_km=0.8,
            per_minute=0.15,
            max_passengers=2,
            description="A shared ride with other passengers going the same way; up to 2 seats, may stop "
            "on the way.",
        ),
    }


class Quotation(BaseModel):
    """The price of a ride between two places with one service type at one pickup time."""

    model_config = ConfigDict(extra="forbid")

    quotation_id: str
    start_location: str
    end_location: str
    service_type: str
    pickup_time: SimTime
    distance_km: float = Field(gt=0)
    duration_minutes: int = Field(ge=1)
    price: float = Field(ge=0)
    peak_pricing: bool = Field(default=False, description="whether the peak-hour multiplier 1.25 applies")


class Ride(BaseModel):
    """A booked ride, current or past."""

    model_config = ConfigDict(extra="forbid")

    ride_id: str
    start_location: str
    end_location: str
    service_type: str
    pickup_time: SimTime
    distance_km: float = Field(gt=0)
    duration_minutes: int = Field(ge=1)
    price: float = Field(ge=0)
    status: RideStatus = "booked"
    driver_name: str | None = None
    vehicle: str | None = Field(default=None, description="e.g. 'white Toyota Prius, plate KX 4821'")
    booked_at: SimTime
    cancellation_reason: str | None = None


class CabState(BaseModel):
    """Service types, the quotations given, every ride by id, and the ride under way."""

    model_config = ConfigDict(extra="forbid")

    service_types: dict[str, ServiceType] = Field(default_factory=default_service_types)
    quotations: dict[str, Quotation] = Field(default_factory=dict)
    rides: dict[str, Ride] = Field(default_factory=dict)
    current_ride_id: str | None = Field(default=None, description="the ride that has not ended, if any")
    known_distances: dict[str, float] = Field(
        default_factory=dict,
        description='distances in km between two places, keyed "A|B" (either order), e.g. '
        '{"Home|Airport": 21.4}; other pairs get a distance from a hash of their names',
    )

    @model_validator(mode="after")
    def _check(self) -> CabState:
        if not self.service_types:
            raise ValueError("there must be at least one service type")
        for key, quotation in self.quotations.items():
            if key != quotation.quotation_id:
                raise ValueError(
                    f"quotation stored under '{key}' has quotation_id '{quotation.quotation_id}'"
                )
        for key, ride in self.rides.items():
            if key != ride.ride_id:
                raise ValueError(f"ride stored under '{key}' has ride_id '{ride.ride_id}'")
        active = [ride.ride_id for ride in self.rides.values() if ride.status in ACTIVE_STATUSES]
        if self.current_ride_id is not None:
            if self.current_ride_id not in self.rides:
                raise ValueError(f"current_ride_id '{self.current_ride_id}' is not a ride")
            if self.rides[self.current_ride_id].status not in ACTIVE_STATUSES:
                raise ValueError(f"current ride '{self.current_ride_id}' has already ended")
        if active and active != [self.current_ride_id]:
            raise ValueError(
                f"rides {active} have not ended; only one may be under way and it must be current_ride_id"
            )
        normalized: dict[str, float] = {}
        for key, km in self.known_distances.items():
            parts = key.split("|")
            if len(parts) != 2 or not all(_norm(p) for p in parts):
                raise ValueError(f'known_distances key {key!r} must name two places as "A|B"')
            if _norm(parts[0]) == _norm(parts[1]):
                raise ValueError(f"known_distances key {key!r} names the same place twice")
            if not 0.1 <= km <= 1000:
                raise ValueError(f"known_distances[{key!r}] must be between 0.1 and 1000 km")
            pair = _pair_key(parts[0], parts[1])
            if pair in normalized and normalized[pair] != round(km, 1):
                raise ValueError(f"known_distances gives two distances for the pair {key!r}")
            normalized[pair] = round(km, 1)
        return self


class RidePage(Paged):
    """One page of rides, most recent first."""

    rows_field = "rides"

    rides: list[Ride]
    total: int
    offset: int
    current_ride_id: str | None = Field(description="the ride under way, if any")


def _norm(place: str) -> str:
    """A place name compared ignoring case and extra spaces."""
    return " ".join(place.split()).casefold()


def _clean(place: str) -> str:
    """A place name as stored: trimmed, inner runs of spaces made single."""
    return " ".join(place.split())


_ABBREVIATIONS = {
    "st": "street", "rd": "road", "ave": "avenue", "av": "avenue", "ln": "lane", "tce": "terrace",
    "terr": "terrace", "dr": "drive", "sq": "square", "pl": "place", "ct": "court", "cres": "crescent",
    "stn": "station", "intl": "international", "hosp": "hospital", "apt": "airport", "nth": "north",
    "sth": "south",
}  # fmt: skip
_FILLER = frozenset({"the", "of", "and", "at"})


def _place_words(place: str) -> frozenset[str]:
    """A place's words, case and punctuation aside, common abbreviations written out."""
    words = re.findall(r"[^\W_]+", place.casefold())
    return frozenset(_ABBREVIATIONS.get(word, word) for word in words if word not in _FILLER)


def _fit(asked: frozenset[str], known: frozenset[str]) -> int | None:
    """How far a place as asked is from a known one (0: the same words), or ``None`` when it is not it:
    one's words must hold all of the other's.
    """
    if not asked or not known:
        return None
    if asked <= known or known <= asked:
        return len(asked ^ known)
    return None


def _pair_key(start: str, end: str) -> str:
    """The same text for a pair of places in either order."""
    return json.dumps(sorted((_norm(start), _norm(end))))


def _money(value: Decimal) -> float:
    return float(value.quantize(Decimal("0.01"), rounding=ROUND_HALF_UP))


def _route(ride: Ride | Quotation) -> str:
    return f"{ride.start_location} → {ride.end_location}"


class CabApp(App):
    """The ride-hailing app."""

    name = "cab"
    title = "Cab"
    description = "Ride-hailing: price quotes between two places, booking a cab, following the current ride."
    State = CabState
    # a booking and a cancellation can be reversed only by another booking, at the fare of the moment
    harm = {
        "order_ride": "costly",
        "order_quotation": "costly",
        "user_cancel_ride": "costly",
    }
    state: CabState

    # -- helpers used by screens --------------------------------------------------------------------
    def records_dated_after(self, now: datetime) -> list[DatedRecord]:
        """See :meth:`App.records_dated_after`."""
        return [
            DatedRecord(
                ("rides", key, "booked_at"), f"ride '{ride.ride_id}' booked {ride.booked_at:%Y-%m-%d %H:%M}"
            )
            for key, ride in self.state.rides.items()
            if ride.booked_at > now
        ]

    def require_ride(self, ride_id: str) -> Ride:
        """Return the ride with ``ride_id``; raise a :class:`ToolError` naming it otherwise."""
        ride = self.state.rides.get(ride_id)
        if ride is None:
            raise ToolError(f"No ride with id '{ride_id}'. Use get_ride_history to find ride ids.")
        return ride

    def require_quotation(self, quotation_id: str) -> Quotation:
        """Return the quotation with ``quotation_id``; raise a :class:`ToolError` naming it otherwise."""
        quotation = self.state.quotations.get(quotation_id)
        if quotation is None:
            raise ToolError(
                f"No quotation with id '{quotation_id}'. Use get_quotation or list_rides to get a quotation."
            )
        return quotation

    def current_ride(self) -> Ride | None:
        """The ride under way, if any."""
        if self.state.current_ride_id is None:
            return None
        return self.state.rides[self.state.current_ride_id]

    def distance_km(self, start: str, end: str) -> float:
        """The road distance between two places, in km with one decimal (symmetric, deterministic).

        A pair the scenario knows is found however its places are written: "22 Fenwick Rd" is "22 Fenwick
        Road", and "Harbour Street Station" is "Harbour Street" (a name that holds all the words of a known
        place, or whose words a known place holds). Of several known pairs that fit, the closest wins.
        """
        pair = _pair_key(start, end)
        known = self._known_distance(start, end)
        if known is not None:
            return round(known, 1)
        digest = hashlib.sha256(pair.encode("utf-8")).digest()
        span = MAX_DISTANCE_TENTHS - MIN_DISTANCE_TENTHS + 1
        return (MIN_DISTANCE_TENTHS + int.from_bytes(digest[:8], "big") % span) / 10

    def _known_distance(self, start: str, end: str) -> float | None:
        wanted = (_place_words(start), _place_words(end))
        best: tuple[int, float] | None = None
        for key, km in self.state.known_distances.items():
            a, b = (_place_words(part) for part in key.split("|"))
            for first, second in ((a, b), (b, a)):
                near_start, near_end = _fit(wanted[0], first), _fit(wanted[1], second)
                if near_start is None or near_end is None:
                    continue
                if best is None or near_start + near_end < best[0]:
                    best = (near_start + near_end, km)
        return None if best is None else best[1]

    def _service(self, service_type: str) -> str:
        """The service type's name as the app spells it (matched case-insensitively)."""
        wanted = service_type.strip()
        if wanted in self.state.service_types:
            return wanted
        for name in self.state.service_types:
            if name.casefold() == wanted.casefold():
                return name
        raise ToolError(
            f"No service type '{service_type}'. Service types: {', '.join(self.state.service_types)}."
        )

    def _places(self, start_location: str, end_location: str) -> tuple[str, str]:
        start, end = _clean(start_location), _clean(end_location)
        if not start or not end:
            raise ToolError("Both start_location and end_location must be given, e.g. '12 Oak St' and 'SFO'.")
        if _norm(start) == _norm(end):
            raise ToolError(f"The start and the end are the same place ('{start}').")
        return start, end

    def _pickup(self, ride_time: datetime | None) -> datetime:
        now = self.ctx.now()
        if ride_time is None:
            return now
        pickup = ensure_utc(ride_time)
        if pickup < now:
            raise ToolError(
                f"The pickup time {pickup:%Y-%m-%d %H:%M} is in the past (it is now {now:%Y-%m-%d %H:%M}). "
                "Give a later time, or leave ride_time out for a ride now."
            )
        return pickup

    def _price(
        self, service: ServiceType, distance: float, minutes: int, pickup: datetime
    ) -> tuple[float, bool]:
        raw = (
            Decimal(str(service.base_fare))
            + Decimal(str(service.per_km)) * Decimal(str(distance))
            + Decimal(str(service.per_minute)) * minutes
        )
        peak = pickup.hour in PEAK_HOURS
        return _money(raw * PEAK_MULTIPLIER if peak else raw), peak

    def _quote(self, start: str, end: str, service_type: str, pickup: datetime) -> Quotation:
        """A quotation, not stored yet (its id is empty); the arguments are already checked."""
        service = self.state.service_types[service_type]
        distance = self.distance_km(start, end)
        tenths = round(distance * 10)
        minutes = max(1, -(-tenths * 60 // (SPEED_KMH * 10)))
        price, peak = self._price(service, distance, minutes, pickup)
        return Quotation(
            quotation_id="",
            start_location=start,
            end_location=end,
            service_type=service_type,
            pickup_time=pickup,
            distance_km=distance,
            duration_minutes=minutes,
            price=price,
            peak_pricing=peak,
        )

    def _store(self, quotation: Quotation) -> Quotation:
        """Store a new quotation; an identical one already stored is returned instead."""
        fields = quotation.model_dump(exclude={"quotation_id"})
        for stored in self.state.quotations.values():
            if stored.model_dump(exclude={"quotation_id"}) == fields:
                return stored
        quotation_id = self.new_id("quote", self.state.quotations)
        stored = quotation.model_copy(update={"quotation_id": quotation_id})
        self.state.quotations[quotation_id] = stored
        return stored

    def _check_no_active_ride(self) -> None:
        ride = self.current_ride()
        if ride is not None:
            raise ToolError(
                f"You already have a ride under way ({ride.ride_id}, {_route(ride)}, status {ride.status}). "
                "Only one ride at a time: cancel it with user_cancel_ride or wait until it ends."
            )

    def _book(self, quotation: Quotation) -> Ride:
        """Book a ride at exactly the quotation's time and price (every check done before)."""
        ride_id = self.new_id("ride", self.state.rides)
        ride = Ride(
            ride_id=ride_id,
            start_location=quotation.start_location,
            end_location=quotation.end_location,
            service_type=quotation.service_type,
            pickup_time=quotation.pickup_time,
            distance_km=quotation.distance_km,
            duration_minutes=quotation.duration_minutes,
            price=quotation.price,
            booked_at=self.ctx.now(),
        )
        self.state.rides[ride_id] = ride
        self.state.current_ride_id = ride_id
        return ride

    def _require_current(self) -> Ride:
        ride = self.current_ride()
        if ride is None:
            raise ToolError("There is no ride under way.")
        return ride

    def _set(self, ride: Ride, **changes: object) -> Ride:
        updated = ride.model_copy(update=changes)
        self.state.rides[ride.ride_id] = updated
        if updated.status not in ACTIVE_STATUSES:
            self.state.current_ride_id = None
        return updated

    # -- agent API -----------------------------------------------------------------------------------
    @tool("read")
    def list_service_types(self) -> dict[str, ServiceType]:
        """List the kinds of ride offered (e.g. Default, Premium, Van, Pool) with their fares and seats.

        A ride costs base_fare + per_km * distance + per_minute * duration, times 1.25 for pickups between
        07:00-09:59 and 16:00-18:59.

        Returns:
            each service type's name with its base fare, price per km, price per minute, maximum number of
            passengers and description.
        """
        return dict(self.state.service_types)

    @tool("read")
    def list_rides(
        self, start_location: str, end_location: str, ride_time: SimTime | None = None
    ) -> list[Quotation]:
        """Get a price quotation for a ride between two places with every service type.

        Each quotation is kept and can be booked as it is with order_quotation.

        Args:
            start_location: where to be picked up, e.g. "12 Oak St" or "Home".
            end_location: where to go, e.g. "SFO Terminal 2".
            ride_time: the pickup time, ISO 8601 in UTC, e.g. "2025-03-04 08:30"; now when left out. It
                cannot be in the past.

        Returns:
            one quotation per service type, with its id, distance, duration, pickup time and price.
        """
        start, end = self._places(start_location, end_location)
        pickup = self._pickup(ride_time)
        quotes = [self._quote(start, end, name, pickup) for name in self.state.service_types]
        return [self._store(quote) for quote in quotes]

    @tool("read")
    def get_quotation(
        self, start_location: str, end_location: str, service_type: str, ride_time: SimTime | None = None
    ) -> Quotation:
        """Get the price of a ride between two places with one service type.

        The quotation is kept and can be booked as it is with order_quotation.

        Args:
            start_location: where to be picked up, e.g. "12 Oak St".
            end_location: where to go, e.g. "SFO Terminal 2".
            service_type: the kind of ride, e.g. "Default" or "Premium"; list_service_types lists them.
            ride_time: the pickup time, ISO 8601 in UTC, e.g. "2025-03-04 08:30"; now when left out. It
                cannot be in the past.

        Returns:
            the quotation, with its id, distance, duration, pickup time and price.
        """
        start, end = self._places(start_location, end_location)
        service = self._service(service_type)
        pickup = self._pickup(ride_time)
        return self._store(self._quote(start, end, service, pickup))

    @tool("read")
    def get_current_ride_status(self) -> Ride | str:
        """Get the ride under way (booked and not yet completed or cancelled): its status, driver and
        vehicle.

        Returns:
            the current ride, or a sentence saying that none is under way (a state, not an error).
        """
        ride = self.current_ride()
        if ride is None:
            return NO_RIDE_UNDER_WAY
        return ride

    @tool("read")
    def get_ride(self, ride_id: str) -> Ride:
        """Get one ride's details, current or past.

        Args:
            ride_id: the ride's id, e.g. "ride-3".

        Returns:
            the ride.
        """
        return self.require_ride(ride_id)

    @tool("read")
    def get_ride_history(self, offset: int = 0, limit: int = PAGE) -> RidePage:
        """List every ride booked, the current one included, most recently booked first, a page at a time.

        Args:
            offset: how many rides to skip.
            limit: how many rides to return (1-100).

        Returns:
            the page of rides, the total number of rides and the id of the ride under way, if any.
        """
        if offset < 0 or not 1 <= limit <= 100:
            raise ToolError("offset must be >= 0 and limit between 1 and 100.")
        ordered = [
            ride
            for _, ride in sorted(
                enumerate(self.state.rides.values()),
                key=lambda item: (item[1].booked_at, item[0]),
                reverse=True,
            )
        ]
        return RidePage(
            rides=ordered[offset : offset + limit],
            total=len(ordered),
            offset=offset,
            current_ride_id=self.state.current_ride_id,
        )

    @tool("write")
    def order_ride(
        self, start_location: str, end_location: str, service_type: str, ride_time: SimTime | None = None
    ) -> Ride:
        """Book a ride between two places with a service type, at the quoted price.

        Only one ride can be under way at a time.

        Args:
            start_location: where to be picked up, e.g. "12 Oak St".
            end_location: where to go, e.g. "SFO Terminal 2".
            service_type: the kind of ride, e.g. "Default" or "Premium"; list_service_types lists them.
            ride_time: the pickup time, ISO 8601 in UTC, e.g. "2025-03-04 08:30"; now when left out. It
                cannot be in the past.

        Returns:
            the booked ride, with its id, pickup time and price.
        """
        start, end = self._places(start_location, end_location)
        service = self._service(service_type)
        pickup = self._pickup(ride_time)
        self._check_no_active_ride()
        return self._book(self._store(self._quote(start, end, service, pickup)))

    @tool("write")
    def order_quotation(self, quotation_id: str) -> Ride:
        """Book exactly the ride of a quotation: its places, service type, pickup time and price.

        Only one ride can be under way at a time. A quotation can be booked until 15 minutes after its
        pickup time.

        Args:
            quotation_id: the quotation's id, from get_quotation or list_rides, e.g. "quote-2".

        Returns:
            the booked ride, with its id, pickup time and price.
        """
        quotation = self.require_quotation(quotation_id)
        now = self.ctx.now()
        if quotation.pickup_time + QUOTE_GRACE < now:
            raise ToolError(
                f"Quotation {quotation_id} was for a pickup at {quotation.pickup_time:%Y-%m-%d %H:%M}, which "
                "has passed. Get a new quotation."
            )
        self._check_no_active_ride()
        return self._book(quotation)

    @tool("write")
    def user_cancel_ride(self) -> str:
        """Cancel the ride under way. A ride that has started (in_progress) can no longer be cancelled.

        Returns:
            confirmation.
        """
        ride = self.current_ride()
        if ride is None:
            raise ToolError("There is no ride under way to cancel.")
        if ride.status not in USER_CANCELLABLE:
            raise ToolError(f"Ride {ride.ride_id} is {ride.status} and can no longer be cancelled.")
        self._set(ride, status="cancelled_by_user")
        return f"Cancelled ride {ride.ride_id} ({_route(ride)})."

    # -- the world -----------------------------------------------------------------------------------
    @tool("env", actors=())
    def driver_cancel_ride(self, reason: str = "") -> Ride:
        """The driver cancels the ride under way (before it has started). The user is notified.

        Args:
            reason: why, as the driver gives it, e.g. "Car broke down"; "" for none.

        Returns:
            the cancelled ride.
        """
        ride = self._require_current()
        if ride.status == "in_progress":
            raise ToolError(f"Ride {ride.ride_id} is in progress; a driver cannot cancel it. Use end_ride.")
        why = reason.strip() or None
        cancelled = self._set(ride, status="cancelled_by_driver", cancellation_reason=why)
        self.notify(
            "ride_cancelled",
            "Your driver cancelled your ride",
            subject=_route(ride),
            body=(f"Reason: {why.rstrip('.')}. " if why else "") + "Book another ride in the Cab app.",
            data={"ride_id": ride.ride_id},
        )
        return cancelled

    @tool("env", actors=())
    def update_ride_status(
        self, status: ProgressStatus, driver_name: str | None = None, vehicle: str | None = None
    ) -> Ride:
        """Move the ride under way forward: a driver is assigned, the driver is arriving, the ride starts.

        Statuses only move forward (booked, driver_assigned, arriving, in_progress; steps may be skipped).
        The user is notified.

        Args:
            status: the new status: "driver_assigned", "arriving" or "in_progress".
            driver_name: the driver's name, e.g. "Sam"; kept when left out.
            vehicle: the car, e.g. "white Toyota Prius, plate KX 4821"; kept when left out.

        Returns:
            the ride as it is now.
        """
        ride = self._require_current()
        if ACTIVE_STATUSES.index(status) <= ACTIVE_STATUSES.index(ride.status):
            raise ToolError(
                f"Ride {ride.ride_id} is already {ride.status}; its status can only move forward "
                f"({' -> '.join(ACTIVE_STATUSES)})."
            )
        driver = driver_name.strip() if driver_name and driver_name.strip() else ride.driver_name
        car = vehicle.strip() if vehicle and vehicle.strip() else ride.vehicle
        updated = self._set(ride, status=status, driver_name=driver, vehicle=car)
        who = f"Your driver {driver}" if driver else "Your driver"
        headline = {
            "driver_assigned": f"{who} will pick you up",
            "arriving": f"{who} is arriving",
            "in_progress": f"Your ride to {ride.end_location} has started",
        }[status]
        details = [f"Pickup {ride.pickup_time:%Y-%m-%d %H:%M} at {ride.start_location}."]
        if car:
            details.insert(0, f"Vehicle: {car}.")
        if status == "in_progress":
            details = [f"About {ride.duration_minutes} min to {ride.end_location}."]
        self.notify(
            "ride_status",
            headline,
            subject=_route(ride),
            body=" ".join(details),
            data={"ride_id": ride.ride_id, "status": status},
        )
        return updated

    @tool("env", actors=())
    def end_ride(self) -> Ride:
        """The ride under way reaches its destination and is completed. The user is notified with the price.

        Returns:
            the completed ride.
        """
        ride = self._require_current()
        completed = self._set(ride, status="completed")
        self.notify(
            "ride_completed",
            f"You have arrived at {ride.end_location}",
            subject=_route(ride),
            body=f"Ride completed: ${ride.price:.2f} for {ride.distance_km} km ({ride.service_type}).",
            data={"ride_id": ride.ride_id, "price": ride.price},
        )
        return completed


# -- screens -----------------------------------------------------------------------------------------


def _ride_row(ride: Ride) -> dict[str, Any]:
    """A past ride as the start screen lists it: where, when, with what, how it ended and the price."""
    return {
        "ride_id": ride.ride_id,
        "route": _route(ride),
        "pickup": short_time(ride.pickup_time),
        "service_type": ride.service_type,
        "status": ride.status,
        "price": ride.price,
    }


class CabHome(Screen):
    """Where to? The entry point: ask for prices, open the current ride, see past rides."""

    name = "Home"
    title = "Where to?"

    def display(self, app: CabApp) -> dict[str, Any]:
        """The ride under way, if any, in full, and the most recent rides in short, with their number."""
        history = app.get_ride_history(limit=PAGE)
        current = app.current_ride()
        return {
            "current_ride": current,
            "total_rides": history.total,
            "recent_rides": [_ride_row(ride) for ride in history.rides if ride is not current],
            **showing_screen(history.rides, history.total, "get_ride_history(offset={offset})"),
        }

    @action("Options", kind="read")
    def list_rides(
        self, app: CabApp, start_location: str, end_location: str, ride_time: SimTime | None = None
    ) -> Transition:
        """See the price of a ride between two places for every service type.

        Args:
            start_location: where to be picked up.
            end_location: where to go.
            ride_time: when to be picked up, e.g. "2025-03-04 08:30"; now when left out.
        """
        quotations = app.list_rides(start_location, end_location, ride_time)
        options = RideOptions(
            start_location=_clean(start_location),
            end_location=_clean(end_location),
            ride_time=None if ride_time is None else ensure_utc(ride_time),
            service_types=[quotation.service_type for quotation in quotations],
        )
        return push(options, quotations)

    @action("Ride")
    def open_current_ride(self, app: CabApp) -> Transition:
        """Open the ride under way."""
        ride = app.current_ride()
        if ride is None:
            raise ToolError("You have no ride under way. Use list_rides to book one.")
        return push(RideDetail(ride_id=ride.ride_id), ride)

    @action(kind="read")
    def get_ride_history(self, app: CabApp, offset: int = 0, limit: int = PAGE) -> RidePage:
        """Show your rides, most recent first.

        Args:
            offset: how many rides to skip.
            limit: how many rides to show.
        """
        return app.get_ride_history(offset=offset, limit=limit)


class RideOptions(Screen):
    """The service types for a trip between two places."""

    name = "Options"
    title = "Ride options"
    start_location: str
    end_location: str
    ride_time: SimTime | None = Field(default=None, description="the pickup time; None means now")
    service_types: list[str] = Field(default_factory=list, description="the service types on offer")

    def display(self, app: CabApp) -> dict[str, Any]:
        """The trip and, per service type, its latest quotation (id, price, duration, seats), as
        list_rides gave them; nothing new is quoted, since showing must not change data.
        """
        start, end = _norm(self.start_location), _norm(self.end_location)
        latest: dict[str, Quotation] = {}
        for quote in app.state.quotations.values():  # stored in the order given: later ones win
            same_trip = (_norm(quote.start_location), _norm(quote.end_location)) == (start, end)
            same_time = self.ride_time is None or quote.pickup_time == self.ride_time
            if same_trip and same_time:
                latest[quote.service_type] = quote
        options = []
        for name in self.service_types:
            quotation = latest.get(name)
            service = app.state.service_types.get(name)
            option: dict[str, Any] = {"service_type": name}
            if quotation is not None:
                option.update(
                    quotation_id=quotation.quotation_id,
                    price=quotation.price,
                    duration_minutes=quotation.duration_minutes,
                    pickup=short_time(quotation.pickup_time),
                )
            if service is not None:
                option["max_passengers"] = service.max_passengers
            options.append(option)
        return {"from": self.start_location, "to": self.end_location, "options": options}

    @action(kind="read")
    def list_service_types(self, app: CabApp) -> dict[str, ServiceType]:
        """Show the kinds of ride offered, with their fares and seats."""
        return app.list_service_types()

    @action("Quote")
    def get_quotation(self, app: CabApp, service_type: str) -> Transition:
        """See the price of this trip with one service type.

        Args:
            service_type: the kind of ride, e.g. "Default" or "Premium".
        """
        quotation = app.get_quotation(self.start_location, self.end_location, service_type, self.ride_time)
        return push(RideQuote(quotation_id=quotation.quotation_id), quotation)


class RideQuote(Screen):
    """A price quotation, ready to be booked."""

    name = "Quote"
    title = "Quotation"
    quotation_id: str

    def display(self, app: CabApp) -> Quotation | str:
        """The quotation in full, as show_quotation shows it."""
        quotation = app.state.quotations.get(self.quotation_id)
        return quotation if quotation is not None else f"Quotation {self.quotation_id} no longer exists."

    @action(kind="read")
    def show_quotation(self, app: CabApp) -> Quotation:
        """Show this quotation: places, service type, pickup time, distance, duration and price."""
        return app.require_quotation(self.quotation_id)

    @action("Ride", kind="write")
    def order_ride(self, app: CabApp) -> Transition:
        """Book this ride at the quoted time and price."""
        ride = app.order_quotation(self.quotation_id)
        return replace(RideDetail(ride_id=ride.ride_id), ride)


class RideDetail(Screen):
    """One ride: its status, driver and vehicle."""

    name = "Ride"
    title = "Your ride"
    ride_id: str

    def display(self, app: CabApp) -> Ride | str:
        """The ride as it is now (status, driver, vehicle, pickup, price), as view_ride shows it."""
        ride = app.state.rides.get(self.ride_id)
        return ride if ride is not None else f"Ride {self.ride_id} no longer exists."

    @action(kind="read")
    def view_ride(self, app: CabApp) -> Ride:
        """Show this ride as it is now: status, driver, vehicle, pickup time and price."""
        return app.require_ride(self.ride_id)

    @action("Home", kind="write")
    def cancel_ride(self, app: CabApp) -> Transition:
        """Cancel this ride and return to the start screen."""
        ride = app.require_ride(self.ride_id)
        if app.state.current_ride_id != self.ride_id:
            raise ToolError(f"This ride is {ride.status} and can no longer be cancelled.")
        return back_to("Home", app.user_cancel_ride())


CabApp.set_screens(CabHome, RideOptions, RideQuote, RideDetail)
