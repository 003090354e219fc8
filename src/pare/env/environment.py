"""The environment: apps and kernel put together, and the one door every tool call goes through."""

from __future__ import annotations

import random
import weakref
from collections.abc import Callable, ItemsView, Iterable, Iterator, KeysView, Mapping, ValuesView
from dataclasses import dataclass
from datetime import datetime, timedelta
from typing import Any, ClassVar, cast

import jsonpatch
from pydantic_core import to_jsonable_python

from pare.apps.agent_ui import AgentUIApp
from pare.apps.base import App, AppContext
from pare.apps.registry import CORE_APPS, get_app_class
from pare.apps.screens import BACK, STAY, Screen, Transition, stay
from pare.apps.system import SystemApp
from pare.apps.tools import ToolSpec
from pare.env.attribution import ATTRIBUTED_ACTORS, CONTROL_APPS, Attribution
from pare.env.config import EnvConfig
from pare.env.views import AssistantObservation, NamedTool, ToolResult, UserView
from pare.errors import SimulationBug, ToolError, UserInputError, did_you_mean
from pare.sim.clock import SimClock
from pare.sim.events import EventAction, EventScheduler, ScheduledEvent
from pare.sim.faults import ToolFailureInjector
from pare.sim.log import ActionLog, Actor, AssistantMode, LogEntry, ToolKind
from pare.sim.noise import NOISE_EVENT_PREFIX, NoiseStream
from pare.sim.notifications import NotificationCenter
from pare.sim.rng import UNUSED_STREAM, EpisodeRandom

MODES: tuple[AssistantMode, ...] = ("observe", "execute")
ACTORS: tuple[Actor, ...] = ("user", "assistant", "env", "oracle")
_CONTROL_APPS = CONTROL_APPS
"""Apps whose tools are the turn protocol, not app data: never failed on purpose, never attributed."""


@dataclass(slots=True)
class _Call:
    """One call being dispatched: what the log entry will say, filled in as the call is resolved."""

    actor: Actor
    app: str
    tool: str
    args: dict[str, Any]
    mode: AssistantMode | None
    event_id: str | None
    kind: ToolKind | None = None
    screen: str | None = None


def _misuse(actor: object, tool: object, mode: object) -> str | None:
    """What is wrong with a call's actor, tool name or mode as Python values, if anything."""
    if actor not in ACTORS:
        return f"Unknown actor {actor!r}: calls are made by one of {', '.join(ACTORS)}."
    if not isinstance(tool, str) or not tool:
        return f"The tool name must be a non-empty string, got {tool!r}."
    if mode is not None and mode not in MODES:
        return f"Unknown assistant mode {mode!r}: one of {', '.join(MODES)}."
    if mode is not None and actor != "assistant":
        return f"Only the assistant calls tools in a mode; {actor} was given mode {mode!r}."
    return None


_ToolTables = tuple[
    dict[AssistantMode, dict[str, ToolSpec]], dict[str, ToolSpec], dict[AssistantMode, tuple[NamedTool, ...]]
]
_TOOL_TABLES: dict[tuple[type[App], ...], _ToolTables] = {}


def _tool_tables(classes: tuple[type[App], ...]) -> _ToolTables:
    """The assistant's tools per mode (by qualified name, and as the named tools it is shown) and every
    tool by qualified name, for a phone with these apps.

    Tools belong to app classes, so the tables are the same for every episode on the same phone: they
    are worked out once per set of apps and shared (read only).
    """
    known = _TOOL_TABLES.get(classes)
    if known is None:
        specs = [spec for cls in classes for spec in cls.tools.values()]
        per_mode: dict[AssistantMode, dict[str, ToolSpec]] = {}
        for mode in MODES:
            allowed: set[ToolKind] = {"read"} if mode == "observe" else {"read", "write"}
            per_mode[mode] = {
                spec.qualified_name: spec
                for spec in specs
                if "assistant" in spec.actors
                and (
                    spec.kind in allowed
                    or (spec.kind == "control" and (mode == "observe" or spec.name != "wait"))
                )
            }
        named = {
            mode: tuple(NamedTool(name, spec) for name, spec in table.items())
            for mode, table in per_mode.items()
        }
        known = per_mode, {spec.qualified_name: spec for spec in specs}, named
        _TOOL_TABLES[classes] = known
    return known


_SHELL_CHECKED: set[tuple[type[App], tuple[type[Screen], ...]]] = set()
"""App classes, with the screens they had, known not to redefine a shell tool (screens belong to the
class and are declared once, by :meth:`App.set_screens`)."""


def _check_screens_keep_shell_names(cls: type[App]) -> None:
    """Raise if a screen of ``cls`` has an action named like a shell tool (``go_back``), which would hide
    it; checked once per class, and again each time for a class that failed.
    """
    key = (cls, cls.screens)
    if key in _SHELL_CHECKED:
        return
    shell_names = set(SystemApp.tools) | set(AgentUIApp.tools)
    for screen in cls.screens:
        clash = shell_names & set(screen.actions)
        if clash:
            raise SimulationBug(f"{cls.name}.{screen.screen_name()} redefines shell tools {sorted(clash)}")
    _SHELL_CHECKED.add(key)


class _Siblings(Mapping[str, App]):
    """An environment's apps as its apps reach them (``ctx.apps``: Files for attachments, the shell for
    the apps it opens), holding the environment weakly.

    Apps hold their context; a context holding the environment's apps would close a reference cycle,
    and every episode's world (apps, states, inboxes) would stay in memory until the cyclic garbage
    collector found it, which then runs far more often and for longer. Held weakly, the world is freed
    as soon as its environment is no longer used. Apps live as long as their environment: reaching a
    sibling after it is gone is a bug, said so.
    """

    __slots__ = ("_env",)

    def __init__(self, env: Environment) -> None:
        self._env = weakref.ref(env)

    def _apps(self) -> dict[str, App]:
        env = self._env()
        if env is None:
            raise SimulationBug("an app reached its sibling apps after their environment was discarded")
        return env.apps

    def __getitem__(self, name: str) -> App:
        return self._apps()[name]

    def __iter__(self) -> Iterator[str]:
        return iter(self._apps())

    def __len__(self) -> int:
        return len(self._apps())

    # the dict's own views and lookups, rather than Mapping's, which go through __getitem__ per app
    def __contains__(self, name: object) -> bool:
        return name in self._apps()

    def keys(self) -> KeysView[str]:
        return self._apps().keys()

    def values(self) -> ValuesView[App]:
        return self._apps().values()

    def items(self) -> ItemsView[str, App]:
        return self._apps().items()


class Environment:
    """One episode's world.

    Holds the clock, the apps, the action log, the notification inboxes, the event scheduler and the
    noise stream. Every tool call by any actor goes through :meth:`call`, which checks that the actor may
    make it now, validates the arguments, runs it, records it in the action log and returns a
    :class:`ToolResult`. Bad calls come back as error results (recorded too); nothing is raised to the
    caller and a failed call changes nothing.
    """

    def __init__(self, apps: Iterable[str | App] = (), config: EnvConfig | None = None) -> None:
        self.config = config or EnvConfig()
        self.clock = SimClock(self.config.start_time)
        self.rng = EpisodeRandom(self.config.seed)
        self.notifications = NotificationCenter(self.config.notifications)
        self.log = ActionLog()
        self.scheduler = EventScheduler(self.clock.start)
        self.turn = 0
        self.apps: dict[str, App] = {}
        self._context = AppContext(self.clock, self.notifications, self.rng, _Siblings(self))
        for core in CORE_APPS:
            self._register(get_app_class(core)(self._context))
        for app in apps:
            self._register(get_app_class(app)(self._context) if isinstance(app, str) else app)
        self.system = cast(SystemApp, self.apps["system"])
        self.agent_ui = cast(AgentUIApp, self.apps["agent_ui"])
        failure_rate, noise_rate = self.config.tool_failure_probability, self.config.noise_rate_per_minute
        self._failures = ToolFailureInjector(failure_rate, self._stream("tool_failures", failure_rate > 0))
        self.noise = NoiseStream(
            rate_per_minute=noise_rate,
            start=self.clock.start,
            apps=set(self.apps),
            arrivals=self._stream("noise_arrivals", noise_rate > 0),
            contents=self._stream("noise_contents", noise_rate > 0),
        )
        self._wakeup_apps = [app for app in self.apps.values() if app.wakeup_tool is not None]
        self._assistant_tools, self._all_tools, self._named_assistant_tools = _tool_tables(
            tuple(type(app) for app in self.apps.values())
        )
        self._assistant_cursor = 0
        self._shown_versions: dict[str, int] = {}
        """Per app, its data version (write count) when the user last saw the screen on view."""
        self.attribution = Attribution()
        """Who created or last changed each place of the app data (the user's and assistant's writes)."""

    # -- set-up ---------------------------------------------------------------------------------------
    def _stream(self, name: str, used: bool) -> random.Random:
        """The episode's random stream ``name`` for a feature, or, when the feature is off, a stream that
        is never drawn from (streams are independent by name, so skipping one shifts no other).
        """
        return self.rng.stream(name) if used else UNUSED_STREAM

    def _register(self, app: App) -> None:
        if app.name in self.apps:
            raise UserInputError(f"app '{app.name}' is registered twice")
        app.ctx = self._context
        _check_screens_keep_shell_names(type(app))
        self.apps[app.name] = app

    def app(self, name: str) -> App:
        """The registered app called ``name``."""
        try:
            return self.apps[name]
        except KeyError:
            raise UserInputError(
                f"app '{name}' is not in this environment.{did_you_mean(name, self.apps)} "
                f"Apps: {', '.join(self.apps)}."
            ) from None

    def load(self, seed_data: Mapping[str, Mapping[str, Any]]) -> None:
        """Seed each app's data: ``{"email": {...}, "contacts": {...}}``."""
        for name, data in seed_data.items():
            self.app(name).load(data)

    # -- the one door ---------------------------------------------------------------------------------
    def call(
        self,
        actor: Actor,
        tool: str,
        args: object = None,
        *,
        mode: AssistantMode | None = None,
        event_id: str | None = None,
    ) -> ToolResult:
        """Run ``tool`` for ``actor`` and record it.

        The user calls tools by their plain names as offered on the current screen (``open_email``,
        ``go_back``). Everyone else calls them by qualified names (``email__send_email``). The assistant
        must say which ``mode`` it is in (observe when not said); it may use only that mode's tools.
        """
        misuse = _misuse(actor, tool, mode)
        if misuse is not None:
            # A caller's programming mistake, not an act in the world: nothing is logged (the log only
            # holds the four actors' calls) and nothing is granted; the error says what was wrong.
            return ToolResult(ok=False, error=misuse)
        if actor == "assistant" and mode is None:
            mode = "observe"
        app_name, _, tool_name = tool.partition("__")
        call = _Call(
            actor=actor,
            app=app_name if tool_name else "?",
            tool=tool_name or tool,
            args=dict(args) if isinstance(args, Mapping) else {},
            mode=mode if actor == "assistant" else None,
            event_id=event_id,
        )
        if args is not None and not isinstance(args, Mapping):
            return self._fail(call, f"Arguments must be a JSON object, got {type(args).__name__}.")
        if actor == "user":
            return self._call_user(call, tool)
        return self._call_flat(call, tool)

    def _call_flat(self, call: _Call, tool: str) -> ToolResult:
        if call.mode is not None:
            spec = self._assistant_tools[call.mode].get(tool)
            if spec is None:
                return self._fail(call, self._why_not_for_assistant(tool, call.mode))
        else:
            spec = self._all_tools.get(tool)
            if spec is None:
                return self._fail(call, f"Unknown tool '{tool}'.{did_you_mean(tool, self._all_tools)}")
        call.app, call.tool, call.kind = spec.app, spec.name, spec.kind
        try:
            values = spec.validate(call.args)
        except ToolError as error:
            return self._fail(call, str(error))
        if call.actor == "assistant" and spec.app not in _CONTROL_APPS:
            injected = self._failures.draw(spec.app, spec.name)
            if injected is not None:
                return self._fail(call, injected, injected_failure=True)
        if call.mode is not None and spec.app == "agent_ui":
            self.agent_ui.assistant_mode = call.mode
        before = self._before_write(call, spec)
        result = self._run(call, spec, lambda: spec.func(self.apps[spec.app], **values))
        self._attribute(result, before)
        return result

    def _why_not_for_assistant(self, tool: str, mode: AssistantMode) -> str:
        spec = self._all_tools.get(tool)
        if spec is None:
            known = self._assistant_tools[mode]
            hint = did_you_mean(tool, known)
            return f"Unknown tool '{tool}'.{hint} Tools are named app__tool, e.g. email__list_emails."
        if "assistant" not in spec.actors:
            return f"'{tool}' is not available to the assistant."
        if tool in self._assistant_tools["execute"]:
            return (
                f"'{tool}' changes data, so it is available only in execute mode, after the user has "
                "accepted a proposal. In observe mode use read tools, wait, or send_message_to_user."
            )
        return f"'{tool}' is not available in {mode} mode."

    def _call_user(self, call: _Call, tool: str) -> ToolResult:
        call.screen = self.system.location()
        result = self._dispatch_user(call, tool)
        self._mark_screen_seen()
        return result

    def _dispatch_user(self, call: _Call, tool: str) -> ToolResult:
        screen = self.system.current_screen()
        if screen is not None and tool in screen.actions:
            return self._run_screen_action(
                call, cast(str, self.system.foreground), screen, screen.actions[tool]
            )
        call.app = self.system.foreground or "system"
        for shell_app in (self.system, self.agent_ui):
            spec = shell_app.tools.get(tool)
            if spec is not None and "user" in spec.actors:
                call.app, call.kind = shell_app.name, spec.kind
                if spec.available is not None and not spec.available(shell_app):
                    return self._fail(call, self._unavailable_message(tool))
                result = self._call_shell(call, shell_app, spec)
                if result.ok and shell_app is self.system and self.system.current_screen() is not screen:
                    return self._with_display(result)
                return result
        return self._fail(call, self._unavailable_message(tool))

    def _with_display(self, result: ToolResult) -> ToolResult:
        """``result`` with what the screen the user arrived on displays (opening an app shows its list)."""
        shown = self._screen_display()
        if shown is None:
            return result
        return ToolResult(ok=True, value=result.value, entry=result.entry, screen_display=shown)

    def _screen_display(self) -> Any:
        screen = self.system.current_screen()
        if screen is None:
            return None
        return to_jsonable_python(screen.display(self.apps[cast(str, self.system.foreground)]))

    def _mark_screen_seen(self) -> None:
        """The user has seen the screen on view as its app's data stands now."""
        if self.system.foreground is not None:
            app = self.apps[self.system.foreground]
            self._shown_versions[app.name] = app.write_count

    def _unavailable_message(self, tool: str) -> str:
        here = self.system.location()
        available = ", ".join(t.name for t in self.user_tools())
        elsewhere = [
            f"{app.name} > {screen.screen_name()}"
            for app in self.apps.values()
            for screen in app.screens
            if tool in screen.actions
        ]
        if tool in ("accept_proposal", "reject_proposal"):
            reason = f"'{tool}' is available only while the assistant has a proposal waiting for your answer."
        elif tool in SystemApp.tools:
            reason = f"'{tool}' is not available here ({here})."
        elif elsewhere:
            owners = ", ".join(elsewhere)
            reason = f"'{tool}' is not available on this screen ({here}); it is an action of {owners}."
        else:
            reason = f"Unknown action '{tool}'.{did_you_mean(tool, [t.name for t in self.user_tools()])}"
        return f"{reason} Available now: {available}."

    def _call_shell(self, call: _Call, shell_app: App, spec: ToolSpec) -> ToolResult:
        try:
            values = spec.validate(call.args)
        except ToolError as error:
            return self._fail(call, str(error))
        return self._run(call, spec, lambda: spec.func(shell_app, **values))

    def _run_screen_action(self, call: _Call, app_name: str, screen: Screen, spec: ToolSpec) -> ToolResult:
        app = self.apps[app_name]
        call.app, call.kind = app_name, spec.kind
        try:
            values = spec.validate(call.args)
        except ToolError as error:
            return self._fail(call, str(error))
        writes_before = app.write_count
        draft = screen.model_copy(deep=True)
        before = self._before_write(call, spec)
        failure, outcome = self._attempt(call, spec, lambda: spec.func(screen, app, **values))
        if failure is not None:  # undo what the action did to its screen (a half-typed draft)
            self._restore_screen(app_name, screen, draft)
            return failure
        transition = outcome if isinstance(outcome, Transition) else stay(outcome)
        self._apply_transition(app_name, spec, transition)
        # What the call did decides its kind: a declared write that changed nothing (saving an unchanged
        # event) is logged as ui, any action that ran a backend write as write.
        if app.write_count != writes_before:
            call.kind = "write"
        elif spec.kind == "write":
            call.kind = "ui"
        result = self._succeed(call, transition.result)
        self._attribute(result, before)
        # Landing on a screen shows it, unless the action's own result already is what it shows.
        arrived = transition.how in ("back", "back_to") or (
            transition.how in ("push", "replace") and transition.result is None
        )
        return self._with_display(result) if arrived else result

    def _restore_screen(self, app_name: str, screen: Screen, draft: Screen) -> None:
        """Undo changes a failing action made to its screen's parameters (a half-edited draft)."""
        stack = self.system.stacks[app_name]
        if stack and stack[-1] is screen:
            stack[-1] = draft

    def _apply_transition(self, app_name: str, spec: ToolSpec, transition: Transition) -> None:
        stack = self.system.stacks[app_name]
        declared = spec.leads_to
        how = transition.how
        if how == "stay":
            target = STAY
        elif how == "back":
            if len(stack) > 1:
                stack.pop()
            else:
                stack[-1] = self.apps[app_name].root_screen()
            # An action may declare BACK, or name the screen a back always lands on (Edit -> Detail).
            target = BACK if BACK in declared else stack[-1].screen_name()
        elif how in ("push", "replace"):
            assert transition.screen is not None
            target = transition.screen.screen_name()
            if how == "push":
                stack.append(transition.screen)
            else:
                stack[-1] = transition.screen
        else:
            target = cast(str, transition.target)
            while stack and stack[-1].screen_name() != target:
                stack.pop()
            if not stack:
                stack.append(transition.screen or self.apps[app_name].screen_class(target)())
            elif transition.screen is not None:
                stack[-1] = transition.screen
        if target not in declared:
            raise SimulationBug(
                f"{app_name}: action {spec.name} went to {target!r} but declares leads_to={declared}"
            )

    # -- attribution ----------------------------------------------------------------------------------
    def _before_write(self, call: _Call, spec: ToolSpec) -> dict[str, Any] | None:
        """For a write by an attributed actor: the data, before the call, of every app it can change (its
        own, and those its app declares in ``also_writes``: attachments saved to Files).
        """
        if spec.kind != "write" or call.actor not in ATTRIBUTED_ACTORS or spec.app in _CONTROL_APPS:
            return None
        owner = self.apps[spec.app]
        reached = [spec.app, *(name for name in owner.also_writes if name in self.apps)]
        return {name: self.apps[name].snapshot(shared=True) for name in reached}

    def _attribute(self, result: ToolResult, before: dict[str, Any] | None) -> None:
        """Mark what a successful write changed, in every app whose data it changed."""
        if before is None or not result.ok or result.entry is None:
            return
        entry = result.entry
        for name, data in before.items():
            self.attribution.record(
                entry.actor, entry.index, name, data, self.apps[name].snapshot(shared=True)
            )

    # -- recording ------------------------------------------------------------------------------------
    def _run(self, call: _Call, spec: ToolSpec, body: Callable[[], Any]) -> ToolResult:
        """Run a tool's body and record the outcome."""
        failure, value = self._attempt(call, spec, body)
        return failure if failure is not None else self._succeed(call, value)

    def _attempt(self, call: _Call, spec: ToolSpec, body: Callable[[], Any]) -> tuple[ToolResult | None, Any]:
        """Run a tool's body; an error becomes a recorded error result, a value is returned unrecorded."""
        try:
            return None, body()
        except ToolError as error:
            return self._fail(call, str(error)), None
        except Exception as error:
            if self.config.raise_internal_errors:
                raise
            message = f"Internal error in {spec.app}.{spec.name} ({type(error).__name__}: {error}). "
            return self._fail(call, message + "This is a bug in PARE."), None

    def _succeed(self, call: _Call, value: Any) -> ToolResult:
        result = to_jsonable_python(value)
        entry = self._record(call, ok=True, result=result)
        return ToolResult(ok=True, value=result, entry=entry)

    def _fail(self, call: _Call, error: str, *, injected_failure: bool = False) -> ToolResult:
        entry = self._record(call, ok=False, error=error, injected_failure=injected_failure)
        return ToolResult(ok=False, error=error, entry=entry)

    def _record(
        self,
        call: _Call,
        *,
        ok: bool,
        result: Any = None,
        error: str | None = None,
        injected_failure: bool = False,
    ) -> LogEntry:
        entry = LogEntry(
            index=len(self.log),
            turn=self.turn,
            time=self.clock.now,
            actor=call.actor,
            app=call.app,
            tool=call.tool,
            args=call.args,
            kind=call.kind,
            ok=ok,
            result=result,
            error=error,
            mode=call.mode,
            injected_failure=injected_failure,
            event_id=call.event_id,
            screen=call.screen,
        )
        self.log.append(entry)
        self.scheduler.observe([entry])
        return entry

    # -- what actors see ------------------------------------------------------------------------------
    _NAMED_TOOLS: ClassVar[dict[type, tuple[Mapping[str, ToolSpec], tuple[NamedTool, ...]]]] = {}
    """Per screen class and shell app class: its table of tools, and the tools the user is offered from it."""

    @classmethod
    def _named_tools(
        cls, owner: type, table: Mapping[str, ToolSpec], *, users_only: bool
    ) -> tuple[NamedTool, ...]:
        """The tools of a screen's actions or of a shell app (``users_only``: those the user may call),
        named, made once per class: both tables are class-level and read-only (set when the app class
        is defined), so they are the same at every step. A class given a new table is named again.
        """
        known = cls._NAMED_TOOLS.get(owner)
        if known is None or known[0] is not table:
            items = table.items()
            named = tuple(NamedTool(n, spec) for n, spec in items if not users_only or "user" in spec.actors)
            known = cls._NAMED_TOOLS[owner] = (table, named)
        return known[1]

    def user_tools(self) -> list[NamedTool]:
        """The tools the user can call right now, under the names the user calls them by."""
        tools: list[NamedTool] = []
        screen = self.system.current_screen()
        if screen is not None:
            tools.extend(self._named_tools(type(screen), screen.actions, users_only=False))
        for shell_app in (self.agent_ui, self.system):
            for tool in self._named_tools(type(shell_app), shell_app.tools, users_only=True):
                available = tool.spec.available
                if available is None or available(shell_app):
                    tools.append(tool)
        return tools

    def user_view(self) -> UserView:
        """What the user sees now; the new notifications are marked read."""
        screen = self.system.current_screen()
        pending = self.agent_ui.pending
        update = None
        foreground = self.system.foreground
        changed = (
            foreground is not None
            and self._shown_versions.get(foreground) != self.apps[foreground].write_count
        )
        if changed:
            update = self._screen_display()  # its data changed under the user's eyes: the screen follows
        self._mark_screen_seen()
        return UserView(
            time=self.clock.now.isoformat(),
            app=foreground,
            screen=None if screen is None else screen.label(),
            background_apps=list(self.system.background),
            tools=self.user_tools(),
            notifications=self.notifications.take_unread("user"),
            pending_proposal=None if pending is None else pending.content,
            screen_update=update,
        )

    def assistant_tools(self, mode: AssistantMode) -> list[NamedTool]:
        """The assistant's tools in ``mode``: observe has read tools, ``wait`` and
        ``send_message_to_user``; execute has every app tool and ``send_message_to_user``.
        """
        return list(self._named_assistant_tools[mode])

    def assistant_observation(self) -> AssistantObservation:
        """The user's actions and the notifications since the assistant last looked (marked seen)."""
        since = self.log.since(self._assistant_cursor)
        self._assistant_cursor = len(self.log)
        return AssistantObservation(
            time=self.clock.now.isoformat(),
            user_actions=[entry for entry in since if entry.actor == "user"],
            notifications=self.notifications.take_unread("assistant"),
            executed=[entry for entry in since if entry.actor == "assistant" and entry.mode == "execute"],
        )

    # -- time and events ------------------------------------------------------------------------------
    def begin_turn(self) -> int:
        """Start the next turn; log entries carry the turn number."""
        self.turn += 1
        return self.turn

    def schedule(self, event: ScheduledEvent) -> None:
        """Add a scheduled event."""
        self.scheduler.add(event)

    def next_event_time(self) -> datetime | None:
        """When the next scheduled event or app wakeup (a reminder falling due) is due, or ``None``.

        Noise is left out: distractors alone never keep an episode going.
        """
        return min(
            (t for t in (self.scheduler.next_time(), self._next_wakeup()[0]) if t is not None), default=None
        )

    def _next_wakeup(self) -> tuple[datetime | None, App | None]:
        best: tuple[datetime | None, App | None] = (None, None)
        for app in self._wakeup_apps:
            moment = app.next_wakeup()
            if moment is not None and (best[0] is None or moment < best[0]):
                best = (moment, app)
        return best

    def advance(self, delta: timedelta) -> None:
        """Let ``delta`` of simulated time pass, firing events at their own times on the way."""
        self.advance_to(self.clock.now + delta)

    def advance_to(self, moment: datetime, *, quiet: bool = False) -> None:
        """Move the clock to ``moment``, firing every event, app wakeup and noise arrival due on the way,
        in time order (scheduled events first, then wakeups, then noise, at equal times).

        ``quiet`` marks a jump over idle time (every actor waited): scheduled events and wakeups still
        fire, but no distractors arrive on the way, so jumping to tomorrow's reminder does not bury the
        phone under a day of noise. Noise resumes from ``moment``.
        """
        self._check_decided()
        if quiet:
            self.noise.skip_until(moment)
        while True:
            due = self.scheduler.next_time()
            wakeup, waking_app = self._next_wakeup()
            noise = self.noise.next_time
            upcoming = min((t for t in (due, wakeup, noise) if t is not None), default=None)
            if upcoming is None or upcoming > moment:
                break
            self.clock.advance_to(upcoming)
            if due is not None and due <= upcoming:
                self._fire_scheduled()
            elif wakeup is not None and waking_app is not None and wakeup <= upcoming:
                self._wake(waking_app, wakeup)
            else:
                arrival = self.noise.pop()
                self._fire(arrival.action, arrival.event_id)
        self.clock.advance_to(moment)

    def deliver_reactions(self, until: datetime) -> list[str]:
        """Fire, in time order, the reactions already set in motion (:meth:`EventScheduler.is_reaction`)
        that are due by ``until``, moving the clock to each; a reaction they set off in turn is delivered
        too. Nothing else happens on the way: no other scheduled event, app wakeup or noise (for after
        the last turn, when no one is left to see what is new). Returns the event ids delivered.
        """
        self._check_decided()
        delivered: list[str] = []
        while (due := self.scheduler.pop_reaction(until)) is not None:
            self.clock.advance_to(due.time)
            self._fire(due.event.action, due.event.event_id)
            self.scheduler.complete(due.event.event_id, self.clock.now)
            delivered.append(due.event.event_id)
        return delivered

    def _check_decided(self) -> None:
        """Time may not pass while a reactive event waits for an answer on an entry already logged (a
        judge model's reading): its reaction would be due in the past. Whoever drives the episode
        awaits the answer and calls :meth:`EventScheduler.retest` first.
        """
        if self.scheduler.undecided:
            raise SimulationBug("the clock moved while a reactive event still waited for an answer")

    def _wake(self, app: App, due: datetime) -> None:
        tool = cast(str, app.wakeup_tool)
        self._fire(EventAction(app.name, tool, {}), f"{app.name}:{tool}")
        after = app.next_wakeup()
        if after is not None and after <= due:
            raise SimulationBug(f"{app.name}.{tool} ran at {due} but the app still wants waking at {after}")

    def failed_events(self) -> list[LogEntry]:
        """Scheduled events (not noise) whose call failed: the world did not happen as the scenario said."""
        return [
            entry
            for entry in self.log
            if entry.actor == "env"
            and not entry.ok
            and entry.event_id
            and not entry.event_id.startswith(NOISE_EVENT_PREFIX)
        ]

    def deliver_due_events(self) -> None:
        """Fire everything due at the current time (events, their dependents, noise)."""
        self.advance_to(self.clock.now)

    def _fire_scheduled(self) -> None:
        due = self.scheduler.pop_due(self.clock.now)
        if due is None:
            raise SimulationBug("an event was due but the scheduler released none")
        self._fire(due.event.action, due.event.event_id)
        self.scheduler.complete(due.event.event_id, self.clock.now)

    def _fire(self, action: EventAction, event_id: str) -> ToolResult:
        return self.call("env", f"{action.app}__{action.tool}", action.args, event_id=event_id)

    # -- state ----------------------------------------------------------------------------------------
    def snapshot(self, *, include_navigation: bool = False, shared: bool = False) -> dict[str, Any]:
        """The data of every app as JSON-ready values (and the user's navigation state if asked).

        With ``shared``, apps whose data was never read give their start state's snapshot, shared with
        other episodes of the scenario (:meth:`App.snapshot`): for readers that never change it.
        """
        state = {name: app.snapshot(shared=shared) for name, app in self.apps.items() if name != "system"}
        if include_navigation:
            state["system"] = self.system.snapshot(shared=shared)
        return state

    def shared_snapshot(self) -> dict[str, Any]:
        """:meth:`snapshot` with ``shared``: what the episode's checks and state diff read."""
        return self.snapshot(shared=True)

    @staticmethod
    def diff(before: Mapping[str, Any], after: Mapping[str, Any]) -> list[dict[str, Any]]:
        """The changes from ``before`` to ``after`` as JSON Patch operations (RFC 6902)."""
        patch = jsonpatch.make_patch(dict(before), dict(after))
        return cast(list[dict[str, Any]], list(patch))
