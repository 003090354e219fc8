"""How bad a wrong call of a write tool is: the harm class every app declares for its writes.

A wrong call of a tool that adds a calendar event costs one more call to put right; a wrong order costs
a cancellation, and a wrong payment or sent message cannot be taken back at all. Each app states the
class of each of its write tools in its ``harm`` class attribute, keyed by the tool's method name (read
tools have none)::

    harm: ClassVar[Mapping[str, Harm]] = {"add_reminder": "reversible", "delete_reminder": "irreversible"}

The classes, by what undoing a wrong call takes:

* ``reversible``: another call puts things back and nobody outside the phone has seen it (an event, a
  note, a contact, a file, an edit of any of them, the cart);
* ``costly``: it can be undone, at a price in money, time or someone else's notice (an order, a booking,
  a cancellation, adding someone to a group);
* ``irreversible``: nothing undoes it (a payment, a sent message or email, a deletion).

A tool is classed by the worst a call of it can do: Email's ``delete_email`` moves an email to Trash the
first time and deletes it for good the second, so it is irreversible.

The class is on each tool's :class:`~pare.apps.tools.ToolSpec` (``spec.harm``), checked when the app
class is defined; a test checks that every write tool of every registered app has one.
"""

from __future__ import annotations

import functools
from collections.abc import Callable, Mapping, Sequence
from typing import TYPE_CHECKING, Literal, get_args

from pare.errors import SimulationBug

if TYPE_CHECKING:
    from pare.apps.base import App
    from pare.apps.tools import ToolSpec
    from pare.sim.log import LogEntry

Harm = Literal["reversible", "costly", "irreversible"]
"""How bad a wrong call of a write tool is (see the module's docstring)."""

HARMS: tuple[Harm, ...] = get_args(Harm)
"""The classes from least to most harmful."""

IRREVERSIBLE: Harm = "irreversible"


def classify_tools(owner: str, tools: Mapping[str, ToolSpec], harm: Mapping[str, object]) -> None:
    """Set each write tool's ``harm`` from an app's ``harm`` declaration, checking it.

    Args:
        owner: the app class's name, for errors.
        tools: the app's tools by method name.
        harm: the app's declaration, tool name to class.

    Raises:
        SimulationBug: when the declaration names a tool the app does not have, a tool that is not a
            write, or a class that is not one of :data:`HARMS`.
    """
    for name, value in harm.items():
        spec = tools.get(name)
        if spec is None:
            raise SimulationBug(
                f"{owner}.harm names '{name}', which is not a tool of the app; its tools are "
                f"{', '.join(sorted(tools)) or 'none'}"
            )
        if spec.kind != "write":
            raise SimulationBug(
                f"{owner}.harm classes '{name}', a {spec.kind} tool: only write tools have a harm class"
            )
        if value not in HARMS:
            raise SimulationBug(
                f"{owner}.harm['{name}'] is {value!r}; a harm class is one of {', '.join(HARMS)}"
            )
        spec.harm = value


def unclassified_writes(app: type[App]) -> list[str]:
    """The write tools of ``app`` that its ``harm`` declaration leaves out, sorted."""
    return sorted(name for name, spec in app.tools.items() if spec.kind == "write" and spec.harm is None)


@functools.cache
def tool_harm(app: str, tool: str) -> Harm | None:
    """The class of ``app``'s flat tool ``tool`` (``None`` for a read, an unknown app or tool, and the
    phone's own apps' calls): what a logged call of it risked, whatever app instances an episode had.
    Kept per name: every logged call of every episode asks it, and app classes do not change.
    """
    from pare.apps.registry import (  # the registry imports the apps, which import this
        app_names,
        get_app_class,
    )

    if app not in app_names(include_core=True):
        return None
    spec = get_app_class(app).tools.get(tool)
    return spec.harm if spec is not None else None


def entry_harm(entry: LogEntry) -> Harm | None:
    """The class of the tool a logged call used, when it was a flat API call of a classified write tool
    (a user's screen action, a read or a call of an unknown tool has none).
    """
    if entry.actor == "user":  # screen actions are named per screen, not by the backend tools they run
        return None
    return tool_harm(entry.app, entry.tool)


def harm_by_index(log: Sequence[LogEntry]) -> Callable[[int], Harm | None]:
    """The class of the call at each position of ``log`` (:func:`entry_harm`); ``None`` out of range."""

    def harm_of(index: int) -> Harm | None:
        return entry_harm(log[index]) if 0 <= index < len(log) else None

    return harm_of
