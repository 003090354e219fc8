"""The simulated clock: the only source of "now" inside an episode."""

from __future__ import annotations

from datetime import UTC, datetime, timedelta

from pare.errors import SimulationBug


def ensure_utc(moment: datetime) -> datetime:
    """Return ``moment`` as an aware UTC datetime; naive datetimes are taken to be UTC."""
    if moment.tzinfo is None:
        return moment.replace(tzinfo=UTC)
    return moment.astimezone(UTC)


class SimClock:
    """A clock that moves only when the simulation moves it, and never backwards.

    Wall-clock time never enters the simulation: an episode depends on its seed and on the actors'
    actions, not on how fast a model answers.
    """

    __slots__ = ("_now", "start")

    def __init__(self, start: datetime) -> None:
        self.start = ensure_utc(start)
        self._now = self.start

    @property
    def now(self) -> datetime:
        """The current simulated time (aware, UTC)."""
        return self._now

    @property
    def elapsed(self) -> timedelta:
        """Simulated time since the start of the episode."""
        return self._now - self.start

    def advance(self, delta: timedelta) -> datetime:
        """Move the clock forward by ``delta`` and return the new time."""
        if delta < timedelta(0):
            raise SimulationBug(f"the simulated clock cannot go backwards (advance by {delta})")
        self._now += delta
        return self._now

    def advance_to(self, moment: datetime) -> datetime:
        """Move the clock to ``moment``; a moment in the past leaves the clock where it is."""
        moment = ensure_utc(moment)
        if moment > self._now:
            self._now = moment
        return self._now
