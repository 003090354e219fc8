"""Screens: the user's finite state machine, declared as data next to the actions.

A screen is a pydantic model whose fields are its parameters (the folder shown, the email open, the draft
being written). Its user actions are methods decorated with :func:`action`, each declaring the screens it
may lead to. The declarations are checked at run time (an action that lands somewhere it did not declare
is a :class:`~pare.errors.SimulationBug`), so the FSM that ``pare apps`` lists and draws is the FSM that
runs.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from datetime import date, datetime
from typing import Any, ClassVar, Literal, TypeVar

from pydantic import BaseModel, ConfigDict

from pare.apps.tools import TOOL_MARKER, ToolMeta, ToolSpec
from pare.sim.log import ToolKind

F = TypeVar("F", bound=Callable[..., Any])

STAY = "stay"
"""``leads_to`` value: the action keeps the user on the same screen."""
BACK = "back"
"""``leads_to`` value: the action returns to the previous screen (send, discard, delete)."""


def action(leads_to: str | Sequence[str] = STAY, *, kind: ToolKind = "ui") -> Callable[[F], F]:
    """Declare a screen method as a user action.

    The method takes ``(self, app, **arguments)`` and returns either a plain result (the user stays) or a
    :class:`Transition` built with :func:`stay`, :func:`push`, :func:`replace`, :func:`back` or
    :func:`back_to`.

    Args:
        leads_to: the screen names it may lead to, :data:`STAY` or :data:`BACK`.
        kind: ``read`` for actions that show data, ``ui`` for navigation and drafts. An action that calls a
            backend write method is logged as ``write`` whatever it declares.
    """
    targets = (leads_to,) if isinstance(leads_to, str) else tuple(leads_to)

    def decorate(func: F) -> F:
        setattr(func, TOOL_MARKER, ToolMeta(kind=kind, actors=frozenset({"user"}), leads_to=targets))
        return func

    return decorate


@dataclass(frozen=True, slots=True)
class Transition:
    """What a user action does to the app's back stack, and what the user is shown."""

    how: Literal["stay", "push", "replace", "back", "back_to"]
    result: Any = None
    screen: Screen | None = None
    target: str | None = None


def stay(result: Any = None) -> Transition:
    """Remain on the current screen."""
    return Transition("stay", result)


def push(screen: Screen, result: Any = None) -> Transition:
    """Go to ``screen``; ``go_back`` returns here."""
    return Transition("push", result, screen)


def replace(screen: Screen, result: Any = None) -> Transition:
    """Swap the current screen for ``screen`` (a saved new item opens its detail screen)."""
    return Transition("replace", result, screen)


def back(result: Any = None) -> Transition:
    """Return to the previous screen."""
    return Transition("back", result)


def back_to(target: str, result: Any = None, screen: Screen | None = None) -> Transition:
    """Return to the nearest screen called ``target`` in the stack, replaced by ``screen`` if given.

    When no such screen is in the stack, the stack restarts from ``screen`` (or a default ``target``).
    """
    return Transition("back_to", result, screen, target)


class Screen(BaseModel):
    """A screen of an app; its fields are its parameters."""

    model_config = ConfigDict(extra="forbid", validate_assignment=False)

    name: ClassVar[str] = ""
    """The screen's name in the FSM (``Mailbox``, ``Detail``); the class name when empty."""
    title: ClassVar[str] = ""
    """What the screen shows, one line, for listings and the user's view."""
    actions: ClassVar[dict[str, ToolSpec]] = {}

    @classmethod
    def screen_name(cls) -> str:
        """The screen's name as the FSM knows it."""
        return cls.name or cls.__name__

    def display(self, app: Any) -> Any:
        """What the screen shows when the user arrives on it or when its app's data changes while it is
        open: a compact, JSON-ready value (a page of a list with the ids needed to act, the item open,
        the draft), or ``None`` when the label says everything.

        It is shown to the user, never logged as a call: it must not change any data.
        """
        return None

    def label(self) -> str:
        """The screen with its parameters, e.g. ``Mailbox(folder='INBOX')``; long text is shortened."""
        params = ", ".join(f"{key}={_short(value)}" for key, value in self.model_dump().items())
        return f"{self.screen_name()}({params})"


def _short(value: Any, limit: int = 40) -> str:
    if isinstance(value, datetime | date):
        return repr(value.isoformat())
    if isinstance(value, list):
        return "[" + ", ".join(_short(item, 20) for item in value[:5]) + (", …]" if len(value) > 5 else "]")
    if isinstance(value, str) and len(value) > limit:
        return repr(value[: limit - 1] + "…")
    return repr(value)
