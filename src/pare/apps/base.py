"""The app base class and the context an app runs in."""

from __future__ import annotations

import pickle
from collections.abc import Collection, Iterable, Mapping
from dataclasses import dataclass
from datetime import UTC, datetime
from typing import Any, ClassVar

from pydantic import BaseModel, ValidationError

from pare.apps.harm import Harm, classify_tools
from pare.apps.screens import BACK, STAY, Screen
from pare.apps.tools import ToolSpec, collect_tools
from pare.errors import SimulationBug, UserInputError
from pare.sim.clock import SimClock
from pare.sim.notifications import NotificationCenter, Recipient
from pare.sim.rng import EpisodeRandom


class AppContext:
    """What an app may use from the simulation: the clock, notifications, randomness, its sibling apps."""

    def __init__(
        self,
        clock: SimClock,
        notifications: NotificationCenter,
        rng: EpisodeRandom,
        apps: Mapping[str, App] | None = None,
    ) -> None:
        self.clock = clock
        self.notifications = notifications
        self.rng = rng
        self.apps: Mapping[str, App] = apps if apps is not None else {}

    @classmethod
    def standalone(cls, start: datetime | None = None, seed: int = 0) -> AppContext:
        """A context for using an app on its own (tests, notebooks)."""
        return cls(
            SimClock(start or datetime(2025, 1, 6, 9, 0, tzinfo=UTC)),
            NotificationCenter(),
            EpisodeRandom(seed),
        )

    def now(self) -> datetime:
        """The current simulated time."""
        return self.clock.now

    def notify(
        self,
        app: str,
        kind: str,
        headline: str,
        *,
        subject: str = "",
        body: str = "",
        data: dict[str, Any] | None = None,
        recipients: Iterable[Recipient] = ("user", "assistant"),
        always_full: bool = False,
    ) -> None:
        """Post a notification at the current time."""
        self.notifications.post(
            time=self.clock.now,
            app=app,
            kind=kind,
            headline=headline,
            subject=subject,
            body=body,
            data=data,
            recipients=recipients,
            always_full=always_full,
        )


@dataclass(frozen=True, slots=True)
class DatedRecord:
    """A record of an app's data with its date: where it is in the state, and what it is, for a message."""

    location: tuple[str | int, ...]
    """Where the date is in the app's state (``("emails", "e9", "timestamp")``)."""
    description: str
    """``email 'e9' sent 2025-03-03 10:00``."""

    def __str__(self) -> str:
        return self.description


@dataclass(frozen=True, slots=True)
class SeedState:
    """An app's validated start state as many episodes share it: pickled, each episode unpickling its
    own copy only if it reads the data, and as the snapshot that state gives (what an episode that never
    reads the app's data reports, without building the state at all).
    """

    pickled: bytes
    snapshot: dict[str, Any]
    """Shared by every episode that starts from this state: read it, never change it."""

    @classmethod
    def of(cls, state: BaseModel) -> SeedState:
        """``state`` kept for sharing: it must not change afterwards (its snapshot is taken now)."""
        return cls(pickle.dumps(state, protocol=pickle.HIGHEST_PROTOCOL), state.model_dump(mode="json"))


_DEFAULT_SNAPSHOTS: dict[type[BaseModel], dict[str, Any]] = {}
"""The snapshot of each app's empty ``State()``, by State class (shared, read only)."""


class _LazyState:
    """``App.state``: an app's data, built when first read.

    An episode reads the data of only a few of its apps; building the others' states (unpickling a seed,
    or an empty ``State()``) and dumping them again for every snapshot was a large share of an episode. The
    first read builds the state and stores it in the instance, where every later read finds it without
    coming here (a non-data descriptor, as ``functools.cached_property``). Assigning ``app.state``
    replaces it the same way.
    """

    def __get__(self, app: App | None, owner: type[App]) -> Any:
        if app is None:
            return self
        seed = app._seed
        state = pickle.loads(seed.pickled) if seed is not None else app.State()
        app.__dict__["state"] = state
        return state


class App:
    """An app: typed backend data (``State``), flat API methods (tools) and screens.

    Subclasses set ``name``, ``title``, ``description``, ``State`` (a pydantic model of all their data)
    and ``screens`` (screen classes, the first being the root), and decorate backend methods with
    :func:`pare.apps.tools.tool`. Everything is collected and checked when the class is defined.
    """

    name: ClassVar[str]
    title: ClassVar[str]
    description: ClassVar[str] = ""
    State: ClassVar[type[BaseModel]]
    screens: ClassVar[tuple[type[Screen], ...]] = ()
    tools: ClassVar[dict[str, ToolSpec]] = {}

    harm: ClassVar[Mapping[str, Harm]] = {}
    """How bad a wrong call of each write tool is, by the tool's method name (:mod:`pare.apps.harm`):
    every write tool has a class, read tools have none."""

    also_writes: ClassVar[tuple[str, ...]] = ()
    """Other apps this app's writes can change (saving attachments changes Files). Attribution diffs the
    data of these and of the app itself around each write, and nothing else: a tool that reaches further
    must say so here (a test walks every app's tools to check)."""

    wakeup_tool: ClassVar[str | None] = None
    """An ``env`` tool the environment calls (as the ``env`` actor, logged) when :meth:`next_wakeup` comes
    due: how time-driven changes such as a reminder falling due enter the simulation."""

    state: Any = _LazyState()
    """The app's data (an instance of ``State``), built on first read (:class:`_LazyState`)."""

    def __init_subclass__(cls, **kwargs: Any) -> None:
        super().__init_subclass__(**kwargs)
        if "name" in cls.__dict__:
            cls.tools = collect_tools(cls, app=cls.name, skip=1)
            classify_tools(cls.__name__, cls.tools, cls.harm)

    @classmethod
    def set_screens(cls, *screens: type[Screen]) -> None:
        """Declare the app's screens, the first being the one it opens on.

        Called once at the bottom of the app's module, after the screen classes (whose actions take the
        app as an argument) are defined. Collects every screen's actions and checks that each declared
        target is a screen of this app.
        """
        names = [screen.screen_name() for screen in screens]
        if len(set(names)) != len(names):
            raise SimulationBug(f"{cls.__name__}: two screens share a name: {names}")
        for screen in screens:
            screen.actions = collect_tools(screen, app=cls.name, skip=2)
            for spec in screen.actions.values():
                unknown = [t for t in spec.leads_to if t not in names and t not in (STAY, BACK)]
                if unknown:
                    raise SimulationBug(
                        f"{cls.__name__}: action {screen.screen_name()}.{spec.name} leads to unknown "
                        f"screen(s) {unknown}; screens are {names}"
                    )
        cls.screens = tuple(screens)

    def __init__(self, ctx: AppContext | None = None) -> None:
        self.ctx = ctx or AppContext.standalone()
        self._seed: SeedState | None = None
        """The shared start state, until :attr:`state` is first read (then in ``__dict__``)."""
        self._id_counters: dict[str, int] = {}
        self.write_count = 0
        """Backend writes so far; how a user action is known to have changed data."""

    def next_wakeup(self) -> datetime | None:
        """When the app next needs :attr:`wakeup_tool` called, or ``None``. Calling it must move this on."""
        return None

    @classmethod
    def root_screen(cls) -> Screen:
        """The screen the app opens on."""
        if not cls.screens:
            raise SimulationBug(f"app '{cls.name}' has no screens")
        return cls.screens[0]()

    @classmethod
    def screen_class(cls, name: str) -> type[Screen]:
        """The screen class called ``name``."""
        for screen in cls.screens:
            if screen.screen_name() == name:
                return screen
        raise KeyError(name)

    def snapshot(self, *, shared: bool = False) -> dict[str, Any]:
        """All of the app's data as JSON-ready values.

        With ``shared``, an app whose data was never read returns its start state's snapshot, shared with
        other episodes (and other calls): for readers that do not change it, such as the checks and the
        episode's state diff. Without it, the data is always the caller's own.
        """
        if shared and "state" not in self.__dict__:
            seed = self._seed
            if seed is not None:
                return seed.snapshot
            default = _DEFAULT_SNAPSHOTS.get(self.State)
            if default is None:
                default = _DEFAULT_SNAPSHOTS[self.State] = self.State().model_dump(mode="json")
            return default
        data: dict[str, Any] = self.state.model_dump(mode="json")
        return data

    def load(self, data: Mapping[str, Any], *, where: str = "") -> None:
        """Replace the app's data with ``data`` (seed data), validating it fully."""
        self._id_counters.clear()
        self._seed = None
        try:
            self.state = self.State.model_validate(dict(data))
        except ValidationError as error:
            place = where or f"seed data of app '{self.name}'"
            problems = "; ".join(
                f"{'.'.join(str(p) for p in item['loc']) or '(top)'}: {item['msg']}"
                for item in error.errors()
            )
            raise UserInputError(f"{place}: {problems}") from None
        now = self.ctx.now()
        late = self.records_dated_after(now)
        if late:
            place = where or f"seed data of app '{self.name}'"
            raise UserInputError(
                f"{place}: dated after the episode's start ({now:%Y-%m-%d %H:%M}), which would make later "
                f"edits stamp records before they existed: {'; '.join(map(str, late))}. Give them a time "
                "at or before the start, or make them events that arrive during the episode."
            )

    def adopt(self, state: BaseModel) -> None:
        """Take ``state`` as the app's data: a state that :meth:`load` already validated and checked for
        this same start (a scenario's seed, loaded once), copied for this app alone.
        """
        if type(state) is not self.State:
            raise SimulationBug(f"app '{self.name}' was given a {type(state).__name__}, not its State")
        self._id_counters.clear()
        self._seed = None
        self.state = state

    def adopt_seed(self, seed: SeedState) -> None:
        """Start from ``seed``, a state that :meth:`load` already validated and checked for this same start
        (a scenario's seed, loaded once): the app's own copy is made only if its data is read.
        """
        self._id_counters.clear()
        self.__dict__.pop("state", None)
        self._seed = seed

    def records_dated_after(self, now: datetime) -> list[DatedRecord]:
        """The loaded records that say they already happened (sent, created, placed) after ``now``.

        Seed data describes the phone at the episode's start; such a record would be edited at a
        time before its own creation.
        """
        return []

    def notify(self, kind: str, headline: str, **kwargs: Any) -> None:
        """Post a notification from this app."""
        self.ctx.notify(self.title, kind, headline, **kwargs)

    def new_id(self, prefix: str, taken: Collection[str]) -> str:
        """A fresh id ``prefix-N``, never one used before in this app, even if that item was deleted.

        Numbering continues after the highest ``prefix-N`` ever seen, so an id that other records still
        refer to (a reply's ``in_reply_to``) is never given to a new item. Ids chosen by a scenario are
        skipped. Deterministic for a given history.
        """
        counter = self._id_counters.get(prefix)
        if counter is None:  # first use since the data was loaded: continue after the highest seeded id
            start = len(prefix) + 1
            numbers = [int(i[start:]) for i in taken if i.startswith(prefix + "-") and i[start:].isdigit()]
            counter = max(numbers, default=0)
        counter += 1
        while f"{prefix}-{counter}" in taken:
            counter += 1
        self._id_counters[prefix] = counter
        return f"{prefix}-{counter}"
