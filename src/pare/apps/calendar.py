"""Calendar: the user's events, with tags, places and attendees."""

from __future__ import annotations

from collections.abc import Iterable
from datetime import UTC, date, datetime, time, timedelta
from typing import Any

from pydantic import BaseModel, ConfigDict, Field, model_validator

from pare.apps.base import App
from pare.apps.done import Done, listed
from pare.apps.paging import Paged, showing_screen
from pare.apps.screens import BACK, Screen, Transition, action, back, back_to, push, replace
from pare.apps.text import PAGE, optional_text, unique_names
from pare.apps.tools import tool
from pare.apps.types import SimTime
from pare.errors import ToolError
from pare.sim.clock import ensure_utc


class CalendarEvent(BaseModel):
    """An event in the calendar."""

    model_config = ConfigDict(extra="forbid")

    event_id: str
    title: str
    start_datetime: SimTime
    end_datetime: SimTime
    tag: str | None = Field(default=None, description="e.g. work, family, health")
    description: str | None = None
    location: str | None = None
    attendees: list[str] = Field(default_factory=list, description="names of the people taking part")

    @model_validator(mode="after")
    def _ends_after_start(self) -> CalendarEvent:
        if self.end_datetime <= self.start_datetime:
            raise ValueError(f"event '{self.event_id}' must end after it starts")
        return self


class EventUpdate(BaseModel):
    """Fields to change on an event; fields left out are kept, null removes an optional field."""

    model_config = ConfigDict(extra="forbid")

    title: str | None = None
    start_datetime: SimTime | None = None
    end_datetime: SimTime | None = None
    tag: str | None = None
    description: str | None = None
    location: str | None = None
    attendees: list[str] | None = None


class CalendarState(BaseModel):
    """Every event by id."""

    model_config = ConfigDict(extra="forbid")

    events: dict[str, CalendarEvent] = Field(default_factory=dict)

    @model_validator(mode="after")
    def _keys_are_ids(self) -> CalendarState:
        for key, event in self.events.items():
            if key != event.event_id:
                raise ValueError(f"event stored under '{key}' has event_id '{event.event_id}'")
        return self


class EventPage(Paged):
    """One page of events."""

    rows_field = "events"

    events: list[CalendarEvent]
    total: int
    offset: int


class AgendaDay(BaseModel):
    """The events of one day, as the agenda shows them."""

    day: date
    tag: str | None = Field(description="the tag filter, if any")
    attendee: str | None = Field(description="the attendee filter, if any")
    events: list[CalendarEvent]


class EventDraft(BaseModel):
    """An event being created or edited, not saved yet."""

    event_id: str | None = Field(description="the event being edited; null for a new event")
    title: str | None
    start_datetime: SimTime
    end_datetime: SimTime
    tag: str | None
    description: str | None
    location: str | None
    attendees: list[str]


def _check_range(start: datetime, end: datetime) -> None:
    """Raise a :class:`ToolError` unless ``end`` is after ``start``."""
    if end <= start:
        raise ToolError(f"The end ({end:%Y-%m-%d %H:%M}) must be after the start ({start:%Y-%m-%d %H:%M}).")


def describe_when(start: datetime, end: datetime) -> str:
    """Format a time range for people, e.g. ``Mon 2025-03-03 10:00-11:00``."""
    if start.date() == end.date():
        return f"{start:%a %Y-%m-%d %H:%M}-{end:%H:%M}"
    return f"{start:%a %Y-%m-%d %H:%M} - {end:%a %Y-%m-%d %H:%M}"


def _by_start(events: Iterable[CalendarEvent]) -> list[CalendarEvent]:
    return sorted(events, key=lambda e: (e.start_datetime, e.end_datetime, e.event_id))


class CalendarApp(App):
    """The calendar."""

    name = "calendar"
    title = "Calendar"
    description = "The user's calendar: events with times, places, tags and attendees."
    State = CalendarState
    harm = {
        "add_calendar_event": "reversible",
        "edit_calendar_event": "reversible",
        "delete_calendar_event": "irreversible",
    }
    state: CalendarState

    # -- helpers used by other apps and screens -----------------------------------------------------
    def require(self, event_id: str) -> CalendarEvent:
        """Return the event with ``event_id``; raise a :class:`ToolError` naming it otherwise."""
        event = self.state.events.get(event_id)
        if event is None:
            raise ToolError(
                f"No event with id '{event_id}'. Use search_events or get_calendar_events_from_to to "
                "find event ids."
            )
        return event

    def today(self) -> date:
        """Return the simulated date."""
        return self.ctx.now().date()

    def root_screen(self) -> Agenda:  # type: ignore[override]
        """The agenda of today, in simulated time: a phone's calendar opens on the current day, and says
        which day it is.

        An instance method (the base class's is a class method) because the day comes from the clock;
        the environment always calls it on the app.
        """
        return Agenda(day=self.today())

    def events_between(self, start: datetime, end: datetime) -> list[CalendarEvent]:
        """Return the events overlapping ``[start, end)``, sorted by start."""
        return _by_start(
            e for e in self.state.events.values() if e.start_datetime < end and e.end_datetime > start
        )

    def events_on(self, day: date) -> list[CalendarEvent]:
        """Return the events taking place (at least partly) on ``day``, sorted by start."""
        start = datetime.combine(day, time(0), tzinfo=UTC)
        return self.events_between(start, start + timedelta(days=1))

    def _create(
        self,
        *,
        title: str,
        start_datetime: datetime,
        end_datetime: datetime,
        tag: str | None,
        description: str | None,
        location: str | None,
        attendees: Iterable[str],
        event_id: str | None = None,
    ) -> CalendarEvent:
        """Check and store a new event (every check before the store)."""
        if not title.strip():
            raise ToolError("An event needs a title.")
        start, end = ensure_utc(start_datetime), ensure_utc(end_datetime)
        _check_range(start, end)
        if event_id is not None:
            if not event_id.strip():
                raise ToolError("event_id cannot be empty; leave it out to get a new id.")
            if event_id in self.state.events:
                raise ToolError(f"An event with id '{event_id}' already exists; choose another id.")
        new_id = event_id or self.new_id("event", self.state.events)
        event = CalendarEvent(
            event_id=new_id,
            title=title.strip(),
            start_datetime=start,
            end_datetime=end,
            tag=optional_text(tag),
            description=optional_text(description),
            location=optional_text(location),
            attendees=unique_names(attendees),
        )
        self.state.events[new_id] = event
        return event

    # -- agent API -----------------------------------------------------------------------------------
    @tool("write")
    def add_calendar_event(
        self,
        title: str,
        start_datetime: SimTime,
        end_datetime: SimTime,
        tag: str | None = None,
        description: str | None = None,
        location: str | None = None,
        attendees: list[str] | None = None,
    ) -> Done:
        """Add an event to the user's calendar.

        Args:
            title: what the event is, e.g. "Dentist appointment".
            start_datetime: when it starts, ISO 8601 in UTC, e.g. "2025-03-04 14:00".
            end_datetime: when it ends, after the start, e.g. "2025-03-04 15:00".
            tag: a category, e.g. "work" or "family".
            description: notes about the event.
            location: where it takes place.
            attendees: names of the people taking part, e.g. ["Alice Chen"].

        Returns:
            what was added and when, and the new event's id.
        """
        event = self._create(
            title=title,
            start_datetime=start_datetime,
            end_datetime=end_datetime,
            tag=tag,
            description=description,
            location=location,
            attendees=attendees or [],
        )
        where = f" at {event.location}" if event.location else ""
        who = f" with {listed(event.attendees)}" if event.attendees else ""
        when = describe_when(event.start_datetime, event.end_datetime)
        done = f"Added event {event.event_id} '{event.title}' to the calendar: {when}{where}{who}."
        return Done(done=done, id=event.event_id)

    @tool("write")
    def edit_calendar_event(self, event_id: str, updates: EventUpdate) -> CalendarEvent:
        """Change some fields of an event; fields not given are kept.

        To move an event, give both its new start and its new end.

        Args:
            event_id: the event to change.
            updates: the fields to change, e.g. {"location": "Room 2", "start_datetime": "2025-03-04 15:00",
                "end_datetime": "2025-03-04 16:00"}. Null removes tag, description or location.

        Returns:
            the event as it is now.
        """
        event = self.require(event_id)
        changes = updates.model_dump(exclude_unset=True)
        if not changes:
            raise ToolError("No field to change was given.")
        for required in ("title", "start_datetime", "end_datetime"):
            if required in changes and changes[required] is None:
                raise ToolError(f"An event's {required} cannot be removed; give a new value or leave it out.")
        if "title" in changes:
            if not changes["title"].strip():
                raise ToolError("An event's title cannot be empty.")
            changes["title"] = changes["title"].strip()
        for optional in ("tag", "description", "location"):
            if optional in changes:
                changes[optional] = optional_text(changes[optional])
        if "attendees" in changes:
            changes["attendees"] = unique_names(changes["attendees"] or [])
        start = changes.get("start_datetime", event.start_datetime)
        end = changes.get("end_datetime", event.end_datetime)
        if end <= start:
            raise ToolError(
                f"The event would end ({end:%Y-%m-%d %H:%M}) before it starts ({start:%Y-%m-%d %H:%M}). "
                "To move it, give both start_datetime and end_datetime."
            )
        updated = CalendarEvent.model_validate({**event.model_dump(), **changes})
        self.state.events[event_id] = updated
        return updated

    @tool("write")
    def delete_calendar_event(self, event_id: str) -> str:
        """Delete an event from the calendar.

        Args:
            event_id: the event to delete.

        Returns:
            confirmation.
        """
        event = self.require(event_id)
        del self.state.events[event_id]
        return f"Deleted event {event_id} ({event.title})."

    @tool("read")
    def get_calendar_event(self, event_id: str) -> CalendarEvent:
        """Get one event's details.

        Args:
            event_id: the event's id.

        Returns:
            the event.
        """
        return self.require(event_id)

    @tool("read")
    def get_calendar_events_from_to(
        self, start_datetime: SimTime, end_datetime: SimTime, offset: int = 0, limit: int = PAGE
    ) -> EventPage:
        """List the events that overlap a time window, sorted by start time, a page at a time.

        Args:
            start_datetime: start of the window, ISO 8601 in UTC, e.g. "2025-03-03 00:00".
            end_datetime: end of the window, after the start, e.g. "2025-03-10 00:00".
            offset: how many events to skip.
            limit: how many events to return (1-100).

        Returns:
            the page of events and the total number of events in the window.
        """
        start, end = ensure_utc(start_datetime), ensure_utc(end_datetime)
        _check_range(start, end)
        if offset < 0 or not 1 <= limit <= 100:
            raise ToolError("offset must be >= 0 and limit between 1 and 100.")
        found = self.events_between(start, end)
        return EventPage(events=found[offset : offset + limit], total=len(found), offset=offset)

    @tool("read")
    def read_today_calendar_events(self) -> list[CalendarEvent]:
        """List today's events (today is the phone's current date), sorted by start time.

        Returns:
            the events taking place today, including those that started yesterday or end tomorrow.
        """
        return self.events_on(self.today())

    @tool("read")
    def search_events(self, query: str) -> list[CalendarEvent]:
        """Search events by title, description, location, tag or attendee.

        The search is case-insensitive and every word of the query must match. It matches parts of words
        too: "Priya" finds "Priyanka".

        Args:
            query: words to look for, e.g. "dentist" or "alice standup".

        Returns:
            the matching events, sorted by start time.
        """
        words = query.lower().split()
        if not words:
            raise ToolError("The search query is empty.")
        found = []
        for event in self.state.events.values():
            fields = [event.title, event.description, event.location, event.tag, *event.attendees]
            haystack = " ".join(f for f in fields if f).lower()
            if all(word in haystack for word in words):
                found.append(event)
        return _by_start(found)

    @tool("read")
    def get_all_tags(self) -> list[str]:
        """List the tags used by events.

        Returns:
            every tag in use, sorted alphabetically.
        """
        return sorted({e.tag for e in self.state.events.values() if e.tag}, key=lambda t: (t.lower(), t))

    @tool("read")
    def get_calendar_events_by_tag(self, tag: str) -> list[CalendarEvent]:
        """List the events with a tag (case-insensitive), sorted by start time.

        Args:
            tag: the tag, e.g. "work". get_all_tags lists the tags in use.

        Returns:
            the events with that tag.
        """
        wanted = tag.strip().lower()
        if not wanted:
            raise ToolError("The tag is empty. Use get_all_tags to see the tags in use.")
        return _by_start(e for e in self.state.events.values() if e.tag and e.tag.lower() == wanted)

    # -- the world -----------------------------------------------------------------------------------
    @tool("env", actors=())
    def add_calendar_event_by_attendee(
        self,
        who_add: str,
        title: str,
        start_datetime: SimTime,
        end_datetime: SimTime,
        tag: str | None = None,
        description: str | None = None,
        location: str | None = None,
        attendees: list[str] | None = None,
        event_id: str | None = None,
    ) -> str:
        """Add an event to the user's calendar on someone else's behalf (an invitation).

        The user is notified.

        Args:
            who_add: the name of the person adding it; they become an attendee.
            title: what the event is.
            start_datetime: when it starts, ISO 8601 in UTC.
            end_datetime: when it ends, after the start.
            tag: a category.
            description: notes about the event.
            location: where it takes place.
            attendees: names of the other people taking part.
            event_id: the id to give the event (scenarios refer to it); a new id when left out.

        Returns:
            the event's id.
        """
        who = who_add.strip()
        if not who:
            raise ToolError("who_add cannot be empty.")
        event = self._create(
            title=title,
            start_datetime=start_datetime,
            end_datetime=end_datetime,
            tag=tag,
            description=description,
            location=location,
            attendees=[who, *(attendees or [])],
            event_id=event_id,
        )
        self.notify(
            "event_added",
            f"{who} added an event",
            subject=event.title,
            body=self._where_and_when(event),
            data={"event_id": event.event_id},
        )
        return event.event_id

    @tool("env", actors=())
    def delete_calendar_event_by_attendee(self, who_delete: str, event_id: str) -> str:
        """Remove an event from the user's calendar on an attendee's behalf (a cancellation).

        The user is notified.

        Args:
            who_delete: the name of the attendee removing it.
            event_id: the event to remove.

        Returns:
            confirmation.
        """
        event = self.require(event_id)
        who = next(
            (name for name in event.attendees if name.casefold() == who_delete.strip().casefold()), None
        )
        if who is None:
            raise ToolError(
                f"'{who_delete}' is not an attendee of event {event_id}; its attendees are "
                f"{', '.join(event.attendees) or 'none'}."
            )
        del self.state.events[event_id]
        self.notify(
            "event_removed",
            f"{who} removed an event",
            subject=event.title,
            body=self._where_and_when(event),
            data={"event_id": event_id},
        )
        return f"Event {event_id} ({event.title}) removed by {who}."

    @staticmethod
    def _where_and_when(event: CalendarEvent) -> str:
        when = describe_when(event.start_datetime, event.end_datetime)
        return f"{when} at {event.location}" if event.location else when


# -- screens -----------------------------------------------------------------------------------------


def _row(event: CalendarEvent, day: date) -> dict[str, Any]:
    """An event as a day's agenda shows it: its id, title, times (hours alone when it is within the
    day) and place.
    """
    start, end = event.start_datetime, event.end_datetime
    within = start.date() == day and end.date() == day
    row: dict[str, Any] = {
        "event_id": event.event_id,
        "title": event.title,
        "when": f"{start:%H:%M}-{end:%H:%M}" if within else describe_when(start, end),
    }
    if event.location:
        row["location"] = event.location
    if event.tag:
        row["tag"] = event.tag
    return row


class Agenda(Screen):
    """One day's events, optionally filtered."""

    name = "Agenda"
    title = "Agenda"
    day: date | None = Field(default=None, description="the day shown; None means today")
    tag: str | None = None
    attendee: str | None = None

    def display(self, app: CalendarApp) -> dict[str, Any]:
        """The day's first events, soonest first as list_events lists them (so positions match
        open_event_by_index), with the filters and the number of events that day.
        """
        listing = self.listing(app)
        shown: dict[str, Any] = {"day": f"{listing.day:%a %Y-%m-%d}"}
        if listing.tag is not None:
            shown["tag"] = listing.tag
        if listing.attendee is not None:
            shown["attendee"] = listing.attendee
        shown["total"] = len(listing.events)
        shown["events"] = [_row(event, listing.day) for event in listing.events[:PAGE]]
        shown.update(showing_screen(shown["events"], len(listing.events), "list_events()"))
        return shown

    def listing(self, app: CalendarApp) -> AgendaDay:
        """Return the day's events with the filters applied."""
        day = self.day or app.today()
        events = app.events_on(day)
        if self.tag is not None:
            wanted = self.tag.lower()
            events = [e for e in events if e.tag is not None and e.tag.lower() == wanted]
        if self.attendee is not None:
            who = self.attendee.lower()
            events = [e for e in events if any(who in name.lower() for name in e.attendees)]
        return AgendaDay(day=day, tag=self.tag, attendee=self.attendee, events=events)

    @action(kind="read")
    def list_events(self, app: CalendarApp) -> AgendaDay:
        """Show the events of the day on screen, with the tag and attendee filters applied."""
        return self.listing(app)

    @action(kind="read")
    def search_events(self, app: CalendarApp, query: str) -> list[CalendarEvent]:
        """Search all events (any day) by title, description, location, tag or attendee. It matches parts
        of words too: "Priya" finds "Priyanka".

        Args:
            query: what to look for.
        """
        return app.search_events(query)

    @action("Detail")
    def open_event(self, app: CalendarApp, event_id: str) -> Transition:
        """Open an event's page.

        Args:
            event_id: the event's id.
        """
        return push(EventDetail(event_id=event_id), app.require(event_id))

    @action("Detail")
    def open_event_by_index(self, app: CalendarApp, index: int) -> Transition:
        """Open the event at a position in the list shown by list_events.

        Args:
            index: the event's position in list_events, counting from 0.
        """
        events = self.listing(app).events
        if not 0 <= index < len(events):
            shown = f"positions 0 to {len(events) - 1}" if events else "no events"
            raise ToolError(f"There is no event at position {index}; the list has {shown}.")
        event = events[index]
        return push(EventDetail(event_id=event.event_id), event)

    @action()
    def filter_by_tag(self, app: CalendarApp, tag: str) -> dict[str, Any]:
        """Show only events with a tag; an empty tag removes the filter.

        Args:
            tag: the tag, e.g. "work", or "" to show every tag.
        """
        wanted = tag.strip()
        if wanted:
            tags = app.get_all_tags()
            if wanted.lower() not in {t.lower() for t in tags}:
                raise ToolError(f"No event has the tag '{wanted}'. Tags in use: {', '.join(tags) or 'none'}.")
        self.tag = wanted or None
        return self.display(app)

    @action()
    def filter_by_attendee(self, app: CalendarApp, attendee: str) -> dict[str, Any]:
        """Show only events with an attendee whose name contains this text.

        An empty text removes the filter.

        Args:
            attendee: part of a name, e.g. "alice", or "" to show everyone's events.
        """
        wanted = attendee.strip()
        if wanted and not any(
            wanted.lower() in name.lower() for e in app.state.events.values() for name in e.attendees
        ):
            raise ToolError(f"No event has an attendee matching '{wanted}'.")
        self.attendee = wanted or None
        return self.display(app)

    @action()
    def set_day(self, app: CalendarApp, day: date) -> dict[str, Any]:
        """Show another day.

        Args:
            day: the day to show, e.g. "2025-03-04".
        """
        self.day = day
        return self.display(app)

    @action(kind="read")
    def read_today_calendar_events(self, app: CalendarApp) -> list[CalendarEvent]:
        """Show today's events, whatever day and filters the agenda is set to."""
        return app.read_today_calendar_events()

    @action(kind="read")
    def get_all_tags(self, app: CalendarApp) -> list[str]:
        """Show the tags used by events."""
        return app.get_all_tags()

    @action("Edit")
    def start_create_event(self, app: CalendarApp) -> Transition:
        """Start a new event, from the next full hour for one hour."""
        start = app.ctx.now().replace(minute=0, second=0, microsecond=0) + timedelta(hours=1)
        draft = EventEdit(start_datetime=start, end_datetime=start + timedelta(hours=1))
        return push(draft, draft.draft())


class EventDetail(Screen):
    """One event's page."""

    name = "Detail"
    title = "Event details"
    event_id: str

    def display(self, app: CalendarApp) -> CalendarEvent | str:
        """The event in full, as open_event shows it (or a line saying it is gone)."""
        event = app.state.events.get(self.event_id)
        return event if event is not None else f"Event {self.event_id} is no longer in the calendar."

    @action(kind="read")
    def refresh(self, app: CalendarApp) -> CalendarEvent:
        """Show this event's details as they are now."""
        return app.require(self.event_id)

    @action(kind="read")
    def list_attendees(self, app: CalendarApp) -> list[str]:
        """Show who takes part in this event."""
        return app.require(self.event_id).attendees

    @action("Agenda", kind="write")
    def delete(self, app: CalendarApp) -> Transition:
        """Delete this event and return to the agenda."""
        return back_to("Agenda", app.delete_calendar_event(self.event_id))

    @action("Edit")
    def edit_event(self, app: CalendarApp) -> Transition:
        """Edit this event."""
        event = app.require(self.event_id)
        draft = EventEdit(
            event_id=event.event_id,
            event_title=event.title,
            start_datetime=event.start_datetime,
            end_datetime=event.end_datetime,
            tag=event.tag,
            description=event.description,
            location=event.location,
            attendees=list(event.attendees),
        )
        return push(draft, draft.draft())


class EventEdit(Screen):
    """A new event or changes to an event, not saved yet."""

    name = "Edit"
    title = "Edit event"
    event_id: str | None = Field(default=None, description="the event being edited; None for a new one")
    event_title: str | None = Field(
        default=None, description="the title; the class attribute title names the screen"
    )
    start_datetime: SimTime
    end_datetime: SimTime
    tag: str | None = None
    description: str | None = None
    location: str | None = None
    attendees: list[str] = Field(default_factory=list)

    def draft(self) -> EventDraft:
        """Return the draft as the user sees it."""
        return EventDraft(
            event_id=self.event_id,
            title=self.event_title,
            start_datetime=self.start_datetime,
            end_datetime=self.end_datetime,
            tag=self.tag,
            description=self.description,
            location=self.location,
            attendees=list(self.attendees),
        )

    def display(self, app: CalendarApp) -> EventDraft:
        """The draft as it stands."""
        return self.draft()

    @action()
    def set_title(self, app: CalendarApp, title: str) -> EventDraft:
        """Set the event's title.

        Args:
            title: the title, e.g. "Lunch with Alice".
        """
        if not title.strip():
            raise ToolError("The title cannot be empty.")
        self.event_title = title.strip()
        return self.draft()

    @action()
    def set_time_range(self, app: CalendarApp, start_datetime: SimTime, end_datetime: SimTime) -> EventDraft:
        """Set when the event starts and ends.

        Args:
            start_datetime: the start, e.g. "2025-03-04 12:30".
            end_datetime: the end, after the start, e.g. "2025-03-04 13:30".
        """
        start, end = ensure_utc(start_datetime), ensure_utc(end_datetime)
        _check_range(start, end)
        self.start_datetime, self.end_datetime = start, end
        return self.draft()

    @action()
    def set_tag(self, app: CalendarApp, tag: str) -> EventDraft:
        """Set the event's tag.

        Args:
            tag: a category, e.g. "work", or "" for none.
        """
        self.tag = optional_text(tag)
        return self.draft()

    @action()
    def set_description(self, app: CalendarApp, description: str) -> EventDraft:
        """Set the event's description.

        Args:
            description: notes about the event, or "" for none.
        """
        self.description = optional_text(description)
        return self.draft()

    @action()
    def set_location(self, app: CalendarApp, location: str) -> EventDraft:
        """Set where the event takes place.

        Args:
            location: the place, or "" for none.
        """
        self.location = optional_text(location)
        return self.draft()

    @action()
    def set_attendees(self, app: CalendarApp, attendees: list[str]) -> EventDraft:
        """Replace the list of attendees.

        Args:
            attendees: names of the people taking part, e.g. ["Alice Chen", "Bob Okafor"]; [] for none.
        """
        self.attendees = unique_names(attendees)
        return self.draft()

    @action()
    def add_attendee(self, app: CalendarApp, attendee: str) -> EventDraft:
        """Add a person to the attendees.

        Args:
            attendee: their name, e.g. "Alice Chen".
        """
        name = attendee.strip()
        if not name:
            raise ToolError("The attendee's name is empty.")
        if name.casefold() in {a.casefold() for a in self.attendees}:
            raise ToolError(f"{name} is already an attendee.")
        self.attendees = [*self.attendees, name]
        return self.draft()

    @action()
    def remove_attendee(self, app: CalendarApp, attendee: str) -> EventDraft:
        """Remove a person from the attendees.

        Args:
            attendee: their name as listed, or a part of it that names one attendee, e.g. "alice".
        """
        wanted = attendee.strip().casefold()
        listed = ", ".join(self.attendees) or "none"
        matches = [a for a in self.attendees if a.casefold() == wanted]
        if not matches and wanted:
            matches = [a for a in self.attendees if wanted in a.casefold()]
        if not matches:
            raise ToolError(f"'{attendee}' is not an attendee. Attendees: {listed}.")
        if len(matches) > 1:
            raise ToolError(
                f"'{attendee}' matches several attendees ({', '.join(matches)}); give the full name."
            )
        self.attendees = [a for a in self.attendees if a != matches[0]]
        return self.draft()

    @action("Detail", kind="write")
    def save(self, app: CalendarApp) -> Transition:
        """Save the event and show it: creates it if it is new, updates it otherwise."""
        if self.event_title is None or not self.event_title.strip():
            raise ToolError("The event has no title yet; use set_title before saving.")
        _check_range(self.start_datetime, self.end_datetime)
        if self.event_id is None:
            event_id = app.add_calendar_event(
                title=self.event_title,
                start_datetime=self.start_datetime,
                end_datetime=self.end_datetime,
                tag=self.tag,
                description=self.description,
                location=self.location,
                attendees=self.attendees,
            ).id
            return replace(EventDetail(event_id=event_id), app.require(event_id))
        event = app.require(self.event_id)
        draft = self.draft().model_dump(exclude={"event_id"})
        changes = {key: value for key, value in draft.items() if getattr(event, key) != value}
        if changes:
            event = app.edit_calendar_event(self.event_id, EventUpdate.model_validate(changes))
        return back_to("Detail", event, EventDetail(event_id=self.event_id))

    @action(BACK)
    def discard(self, app: CalendarApp) -> Transition:
        """Leave without saving; nothing changes."""
        return back("Draft discarded.")


CalendarApp.set_screens(Agenda, EventDetail, EventEdit)
