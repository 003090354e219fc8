"""What a person types (or fills in a form) as the user, read into one valid user action.

A person in the user's seat acts on the same screens as the user simulator and is offered the same
actions. They may answer in three ways:

* the action format the user model writes (:mod:`pare.agents.actions`): ``Action: {"action": ...}``, or
  the JSON object alone;
* a tool's name, alone (its arguments are then asked for one by one) or followed by its arguments as a
  JSON object: ``open_app {"app_name": "email"}``;
* a number from the menu of the screen's actions (:func:`menu`), then the arguments one by one.

``wait`` waits and ``quit`` leaves the seat (:class:`SeatLeft`). Anything that cannot be an action on
this screen raises :class:`HumanInputError` with a message for the person (the seat asks again): a tool
not on offer, an argument missing, misspelt or of the wrong type. Such slips are not played, since a person
who mistypes has not acted in the world; what the app itself refuses (an id that does not exist) is
played and recorded like any actor's failed call.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from enum import Enum
from types import UnionType
from typing import Annotated, Any, Literal, Union, get_args, get_origin

from pare.agents.actions import parse_action
from pare.agents.policy import Action
from pare.env import NamedTool, UserView
from pare.errors import ActionFormatError, ToolError, did_you_mean

QUIT = "quit"
"""What a person types to leave the seat."""
HELP = ("help", "?")


class HumanInputError(ValueError):
    """What the person typed is not an action on this screen; the message says why and what to do."""


class SeatLeft(BaseException):
    """The person left the seat (``quit``) before the episode ended.

    A ``BaseException``, like ``KeyboardInterrupt``: it must pass the handlers that record an actor's
    exception as a failed episode, since nothing went wrong in the episode.
    """


@dataclass(frozen=True, slots=True)
class ArgumentField:
    """One argument of a tool, as a person is asked for it."""

    name: str
    type_text: str
    """Its type as the tool's signature writes it, e.g. ``int`` or ``'INBOX' | 'SENT'``."""
    required: bool
    default: Any
    description: str
    text: bool
    """The argument is text: what the person types is taken as it is (not read as JSON)."""


def menu(view: UserView) -> list[NamedTool]:
    """The actions on offer now, in the order of the numbered menu (numbered from 1)."""
    return list(view.tools)


def argument_fields(tool: NamedTool) -> list[ArgumentField]:
    """The arguments of ``tool`` in signature order."""
    fields = []
    signature = tool.spec.signature
    for name, info in tool.spec.params.model_fields.items():
        fields.append(
            ArgumentField(
                name=name,
                type_text=_type_text(signature, name),
                required=info.is_required(),
                default=None if info.is_required() else info.default,
                description=info.description or "",
                text=_is_text(info.annotation),
            )
        )
    return fields


def read_typed_action(text: str, view: UserView) -> Action | ToolChoice:
    """Read one line typed at the ``action>`` prompt.

    Returns the action when the line holds all of it, or a :class:`ToolChoice` when it names a tool
    whose arguments are still to be asked for (a menu number or a bare tool name).

    Raises:
        SeatLeft: The person typed ``quit``.
        HumanInputError: The line is not an action on this screen.
    """
    line = text.strip()
    if not line:
        raise HumanInputError("Type a number from the menu, an action, 'wait' or 'quit' ('help' explains).")
    lowered = line.lower()
    if lowered == QUIT:
        raise SeatLeft
    if line.isdigit():
        tools = menu(view)
        number = int(line)
        if not 1 <= number <= len(tools):
            raise HumanInputError(f"There is no action {number} on this screen: choose 1 to {len(tools)}.")
        return _chosen(tools[number - 1])
    if line.startswith("{") or "action:" in lowered:
        answer = line if "action:" in lowered else f"Action: {line}"
        try:
            parsed = parse_action(answer)
        except ActionFormatError as error:
            raise HumanInputError(str(error)) from None
        return checked_action(view, parsed.tool, parsed.args, raw=text)
    name, _, rest = line.partition(" ")
    tool = find_tool(view, name)
    rest = rest.strip()
    if not rest:
        return _chosen(tool)
    try:
        args = json.loads(rest)
    except json.JSONDecodeError as error:
        raise HumanInputError(
            f"The arguments after {name} must be one JSON object, e.g. {name} "
            f'{{"{_first_argument(tool)}": ...}} ({error.msg} at column {error.colno}).'
        ) from None
    if not isinstance(args, dict):
        raise HumanInputError(f"The arguments after {name} must be a JSON object {{...}}, not {rest!r}.")
    return checked_action(view, tool.name, args, raw=text)


@dataclass(frozen=True, slots=True)
class ToolChoice:
    """A tool the person chose whose arguments are still to be asked for."""

    tool: NamedTool
    fields: list[ArgumentField]


def _chosen(tool: NamedTool) -> Action | ToolChoice:
    fields = argument_fields(tool)
    if not fields:
        return Action(tool.name)
    return ToolChoice(tool, fields)


def find_tool(view: UserView, name: str) -> NamedTool:
    """The tool ``name`` on offer on this screen.

    Raises:
        HumanInputError: No such action here; the message suggests the closest one.
    """
    for tool in view.tools:
        if tool.name == name:
            return tool
    offered = view.tool_names
    raise HumanInputError(
        f"'{name}' is not an action on this screen.{did_you_mean(name, offered)} "
        f"Available: {', '.join(offered)}."
    )


def argument_value(field: ArgumentField, typed: str) -> tuple[bool, Any]:
    """What the person typed for ``field``: ``(False, None)`` when left empty (the default applies), else
    ``(True, value)``; text is taken as typed, other types are read as JSON when they look like JSON
    (``[1, 2]``, ``{"a": 1}``, ``true``) and otherwise left to the tool's validation (``3`` for an int).

    Raises:
        HumanInputError: A required argument was left empty, or a list or object is not valid JSON.
    """
    if typed == "" or (not field.text and not typed.strip()):
        if field.required:
            raise HumanInputError(f"'{field.name}' is required ({field.type_text}).")
        return False, None
    if field.text:
        return True, typed
    stripped = typed.strip()
    if stripped[0] in "[{":
        try:
            return True, json.loads(stripped)
        except json.JSONDecodeError as error:
            raise HumanInputError(
                f"'{field.name}' ({field.type_text}) must be written as JSON here: {error.msg} at column "
                f"{error.colno}."
            ) from None
    if stripped in ("true", "false", "null"):
        return True, json.loads(stripped)
    return True, stripped


def action_from_fields(
    view: UserView, tool_name: str, typed: dict[str, str], raw: str | None = None
) -> Action:
    """The action for ``tool_name`` with the arguments typed into its fields (a form's, or the terminal's
    prompts); fields left empty take their defaults.

    Raises:
        HumanInputError: The tool is not on offer, an argument is missing, unknown or of the wrong type.
    """
    tool = find_tool(view, tool_name)
    fields = {field.name: field for field in argument_fields(tool)}
    unknown = sorted(set(typed) - set(fields))
    if unknown:
        raise HumanInputError(
            f"{tool.name} has no argument '{unknown[0]}'.{did_you_mean(unknown[0], fields)}"
        )
    args: dict[str, Any] = {}
    for name, field in fields.items():
        given, value = argument_value(field, typed.get(name, ""))
        if given:
            args[name] = value
    return checked_action(view, tool.name, args, raw=raw)


def checked_action(view: UserView, tool_name: str, args: dict[str, Any], *, raw: str | None = None) -> Action:
    """The action, once the tool is on offer here and the arguments fit its signature (the values are
    kept as given: the environment validates them again, as for any actor).

    Raises:
        HumanInputError: The tool is not on offer, or the arguments do not fit; the message says how.
    """
    tool = find_tool(view, tool_name)
    try:
        tool.spec.validate(args)
    except ToolError as error:
        raise HumanInputError(str(error)) from None
    return Action(tool.name, dict(args), raw=raw)


def _first_argument(tool: NamedTool) -> str:
    names = list(tool.spec.params.model_fields)
    return names[0] if names else "argument"


def _type_text(signature: str, name: str) -> str:
    """The type the signature gives argument ``name`` (``str``, ``int = 0``'s ``int``)."""
    inside = signature[signature.find("(") + 1 : signature.rfind(")")]
    for part in _split_arguments(inside):
        head, _, annotation = part.partition(":")
        if head.strip() == name:
            return annotation.split(" = ")[0].strip()
    return "value"


def _split_arguments(text: str) -> list[str]:
    """The comma-separated parts of a signature, commas inside brackets and quotes kept."""
    parts: list[str] = []
    current: list[str] = []
    depth, quote = 0, ""
    for char in text:
        if quote:
            quote = "" if char == quote else quote
        elif char in "'\"":
            quote = char
        elif char in "[{(":
            depth += 1
        elif char in "]})":
            depth -= 1
        elif char == "," and depth == 0:
            parts.append("".join(current))
            current = []
            continue
        current.append(char)
    if current:
        parts.append("".join(current))
    return parts


def _is_text(annotation: Any) -> bool:
    """Whether an argument takes text (``str``, a choice of strings, or either or ``None``)."""
    origin = get_origin(annotation)
    if origin in (Union, UnionType):
        kept = [arg for arg in get_args(annotation) if arg is not type(None)]
        return bool(kept) and all(_is_text(arg) for arg in kept)
    if origin is Literal:
        return all(isinstance(arg, str) for arg in get_args(annotation))
    if origin is Annotated:
        return _is_text(get_args(annotation)[0])
    if isinstance(annotation, type) and issubclass(annotation, Enum):
        return all(isinstance(member.value, str) for member in annotation)
    return annotation is str
