"""The system prompts of the user simulator and the assistant's observe and execute modes.

Written in our own words after the paper's appendix, rendered per episode from Jinja templates in
``templates/``: the phone's apps, the current simulated time, the tools (their signatures and docstrings)
and what each actor is told about notifications. With native tool calling, the tools travel as function
schemas and the text answer format is left out.
"""

from __future__ import annotations

import functools
import json
import re
from collections.abc import Hashable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Literal

import jinja2

from pare.agents.policy import ASSISTANT_WAIT, SEND_MESSAGE, Task
from pare.apps.base import App
from pare.apps.registry import CORE_APPS
from pare.env import Environment, NamedTool
from pare.errors import SimulationBug
from pare.sim.budget import DEFAULT_BUDGET, TurnBudget
from pare.sim.notifications import DetailLevel

TEMPLATES = Path(__file__).parent / "templates"


@dataclass(frozen=True, slots=True, eq=False)
class AppLine:
    """An app as a prompt lists it; made once per set of app classes (:func:`_apps`), so compared, and
    hashed in the prompts' cache keys, by identity.
    """

    name: str
    description: str


@dataclass(frozen=True, slots=True)
class ToolLine:
    """A tool as a prompt lists it: signature under the caller's name, and its description."""

    signature: str
    summary: str


@functools.cache
def _templates() -> jinja2.Environment:
    return template_environment(TEMPLATES)


def template_environment(folder: Path) -> jinja2.Environment:
    """A Jinja environment for the plain-text prompt templates in ``folder``: undefined names are errors."""
    return jinja2.Environment(
        loader=jinja2.FileSystemLoader(folder),
        undefined=jinja2.StrictUndefined,
        keep_trailing_newline=True,
        auto_reload=False,  # the templates ship with the package: no need to check their files per render
        trim_blocks=True,
        lstrip_blocks=True,
        autoescape=False,  # plain-text prompts, not HTML
    )


def example_answer(thought: str, tool: str, args: dict[str, Any]) -> str:
    """An answer in the text action format, as the prompts show it."""
    action = json.dumps({"action": tool, "action_input": args}, ensure_ascii=False)
    return f"Thought: {thought}\n\nAction:\n{action}<end_action>"


Role = Literal["user", "observe", "execute"]


@dataclass(frozen=True, slots=True)
class _Example:
    """An example answer a prompt may show: a call of ``tool`` with arguments in the tool's own formats."""

    thought: str
    tool: str
    args: dict[str, Any]

    def answer(self) -> str:
        return example_answer(self.thought, self.tool, self.args)


_ASSISTANT_EXAMPLES: dict[str, tuple[_Example, ...]] = {
    "observe": (
        _Example(
            "The user received an invitation for Friday 7 March; I check the calendar for that day before "
            "proposing.",
            "calendar__get_calendar_events_from_to",
            {"start_datetime": "2025-03-07 00:00", "end_datetime": "2025-03-07 23:59"},
        ),
        _Example(
            "A new email asks about Friday's dinner; I look for earlier emails about it before proposing.",
            "email__search_emails",
            {"query": "dinner friday"},
        ),
        _Example(
            "A message mentions the weekend plans; I search the conversations for them before proposing.",
            "messaging__search",
            {"query": "weekend"},
        ),
        _Example(
            "The user is looking at groceries; I check what is in the cart first.", "shopping__list_cart", {}
        ),
        _Example(
            "The user is searching for a flat; I check which flats they saved first.",
            "apartment__list_saved_apartments",
            {},
        ),
        _Example(
            "A note may hold what the user needs; I search the notes.",
            "notes__search_notes",
            {"query": "list"},
        ),
    ),
    "execute": (
        _Example(
            "The email I must reply to is not among the items I was handed; I search for its id.",
            "email__search_emails",
            {"query": "dinner friday"},
        ),
        _Example(
            "The conversation is not among the items I was handed; I search for its id.",
            "messaging__search",
            {"query": "weekend"},
        ),
        _Example(
            "The event is not among the items I was handed; I search for its id.",
            "calendar__search_events",
            {"query": "dentist"},
        ),
        _Example(
            "The product is not among the items I was handed; I search for its item id.",
            "shopping__search_product",
            {"product_name": "coffee"},
        ),
        _Example(
            "The note is not among the items I was handed; I search for its id.",
            "notes__search_notes",
            {"query": "list"},
        ),
    ),
}
"""The example answers the assistant's prompts may show, in order of preference: a prompt shows the first
whose tool the phone has (the files app, which every phone has, is the last resort)."""

_FILES_EXAMPLE = _Example("I look at the user's files first.", "files__list_directory", {"path": "/"})

_EXAMPLES: dict[tuple[Role, tuple[type[App], ...]], str] = {}


def example_for(env: Environment, role: Role) -> str:
    """The example answer ``role``'s prompt shows on ``env``'s phone: a call of a tool the role has on it,
    with arguments in the tool's own formats (chosen once per set of apps).
    """
    key = (role, _phone(env))
    example = _EXAMPLES.get(key)
    if example is None:
        example = _EXAMPLES[key] = _choose_example(env, role).answer()
    return example


def _choose_example(env: Environment, role: Role) -> _Example:
    if role == "user":
        app = next((line.name for line in _apps(env) if line.name != "files"), "files")
        return _Example(
            f"A new {app} notification came in; I want to see it, so I open the {app} app.",
            "open_app",
            {"app_name": app},
        )
    available = {tool.name for tool in env.assistant_tools(role)}
    return next(
        (example for example in _ASSISTANT_EXAMPLES[role] if example.tool in available), _FILES_EXAMPLE
    )


def _now(env: Environment) -> str:
    return env.clock.now.strftime("%A %Y-%m-%d %H:%M")


def _start(env: Environment) -> str:
    """When the session started: prompts that last the whole episode say this, not a "now" that goes
    stale; every observation carries the current time.
    """
    return env.clock.start.strftime("%A %Y-%m-%d %H:%M")


_APP_LINES: dict[tuple[type[App], ...], tuple[AppLine, ...]] = {}


def _phone(env: Environment) -> tuple[type[App], ...]:
    """The phone's app classes: what the apps and tools a prompt lists depend on (class attributes)."""
    return tuple(type(app) for app in env.apps.values())


def _apps(env: Environment) -> tuple[AppLine, ...]:
    """The apps a prompt lists, made once per set of apps."""
    key = _phone(env)
    lines = _APP_LINES.get(key)
    if lines is None:
        lines = _APP_LINES[key] = tuple(
            AppLine(app.name, app.description)
            for app in env.apps.values()
            if app.name not in CORE_APPS or app.name == "files"
        )
    return lines


def _first_sentence(text: str) -> str:
    head, dot, _ = text.partition(". ")
    return head + "." if dot else text


def execute_only_lines(env: Environment) -> list[ToolLine]:
    """The tools execute mode adds to observe mode's, by name with the first sentence of their
    description: what the assistant will be able to do once a proposal is accepted.
    """
    observe = {tool.name for tool in env.assistant_tools("observe")}
    return [
        ToolLine(tool.name, _first_sentence(tool.spec.summary))
        for tool in env.assistant_tools("execute")
        if tool.name not in observe
    ]


def tool_lines(tools: list[NamedTool]) -> list[ToolLine]:
    """Tools as prompt lines, each under the name its caller uses (``email__send_email(...)``)."""
    lines = []
    for tool in tools:
        arguments = tool.spec.signature[len(tool.spec.name) :]
        lines.append(ToolLine(f"{tool.name}{arguments}", tool.spec.summary))
    return lines


@dataclass(frozen=True, slots=True)
class _AssistantToolLists:
    """The assistant's tools as its prompts list them for one phone's apps: ``_tools.j2``'s text."""

    observe: str
    execute: str
    execute_only: str


_ASSISTANT_TOOL_LISTS: dict[tuple[type[App], ...], _AssistantToolLists] = {}


def _assistant_tool_lists(env: Environment) -> _AssistantToolLists:
    """The assistant's tool lists for ``env``'s phone, written once per set of apps.

    The assistant's tools are the tools of the phone's app classes (the environment's tool tables are
    per set of app classes too), so every episode on the same phone lists the same tools; the lists
    are text, so episodes can share them.
    """
    key = _phone(env)
    lists = _ASSISTANT_TOOL_LISTS.get(key)
    if lists is None:
        lists = _AssistantToolLists(
            observe=_tool_list(tool_lines(env.assistant_tools("observe"))),
            execute=_tool_list(tool_lines(env.assistant_tools("execute"))),
            execute_only=_tool_list(execute_only_lines(env)),
        )
        _ASSISTANT_TOOL_LISTS[key] = lists
    return lists


def _tool_list(lines: list[ToolLine]) -> str:
    """Tool lines as a prompt lists them, one line each (empty for none)."""
    return _templates().get_template("_tools.j2").render(tools=lines)


_USER_NOTIFICATIONS: dict[DetailLevel, str] = {
    "minimal": "Notifications show only which app has news and from whom; open the app to read it.",
    "preview": "Notifications show who it is from, the subject and the first {words} words; "
    "open the app to read the rest.",
    "full": "Notifications show the full text of what arrived.",
}


_WHOLE_FOR_THE_USER = (
    " Your assistant's messages to you (its reports, and the notice that a proposal was withdrawn) are"
    " always shown in full."
)
"""What arrives whole whatever the user's level: the notifications posted ``always_full``."""
_WHOLE_WITHOUT_EXPIRY = " Your assistant's messages to you (its reports) are always shown in full."
"""The same when proposals never expire (no withdrawal notice to come)."""


def _user_notifications(env: Environment, budget: TurnBudget) -> str:
    policy = env.config.notifications
    text = _USER_NOTIFICATIONS[policy.user].format(words=policy.preview_words)
    if policy.user == "full":
        return text
    return text + (_WHOLE_FOR_THE_USER if budget.proposal_ttl_turns is not None else _WHOLE_WITHOUT_EXPIRY)


def _assistant_notifications(env: Environment) -> str:
    level = env.config.notifications.assistant
    if level == "full":
        return "You receive every notification in full, as soon as it arrives."
    return f"You receive notifications at the '{level}' level; read the app to see everything."


def user_system_prompt(
    env: Environment,
    *,
    persona: str | None = None,
    goal: str | None = None,
    native_tools: bool = False,
    budget: TurnBudget = DEFAULT_BUDGET,
) -> str:
    """The user simulator's system prompt for ``env``, with the scenario's persona and hidden goal."""
    return _render(
        "user.j2",
        native_tools,
        {"start": _start(env), "persona": persona, "goal": goal},
        apps=_apps(env),
        budget=budget,
        notification_policy=_user_notifications(env, budget),
        example=example_for(env, "user"),
    )


def observe_system_prompt(
    env: Environment, *, native_tools: bool = False, budget: TurnBudget = DEFAULT_BUDGET
) -> str:
    """The assistant's system prompt in observe mode."""
    return _render(
        "observe.j2",
        native_tools,
        {"start": _start(env)},
        apps=_apps(env),
        budget=budget,
        notification_policy=_assistant_notifications(env),
        propose_tool=SEND_MESSAGE,
        wait_tool=ASSISTANT_WAIT,
        tools=_assistant_tool_lists(env).observe,
        execute_tools=_assistant_tool_lists(env).execute_only,
        example=example_for(env, "observe"),
    )


def execute_system_prompt(env: Environment, task: Task, *, max_steps: int, native_tools: bool = False) -> str:
    """The assistant's system prompt in execute mode, holding the accepted task and the user's answer."""
    return _render(
        "execute.j2",
        native_tools,
        {"now": _now(env), "proposal": task.proposal, "answer": task.answer},
        apps=_apps(env),
        report_tool=SEND_MESSAGE,
        max_steps=max_steps,
        tools=_assistant_tool_lists(env).execute,
        example=example_for(env, "execute"),
    )


_HOLE = "\x00hole:{}\x00"
"""What a skeleton holds in place of a per-episode value: a text no template or tool list contains."""
_HOLE_RE = re.compile("\x00hole:(\\w+)\x00")


@dataclass(frozen=True, slots=True)
class _Skeleton:
    """A prompt rendered with a hole for each per-episode value: the text around the holes (one more
    piece than holes) and the name of each hole, in order.
    """

    pieces: tuple[str, ...]
    holes: tuple[str, ...]

    @classmethod
    def of(cls, text: str) -> _Skeleton:
        split = _HOLE_RE.split(text.strip() + "\n")
        pieces, holes = tuple(split[0::2]), tuple(split[1::2])
        # at the edge of the prompt, a value's own surrounding whitespace would be stripped by _render
        if holes and not (pieces[0] and pieces[-1].strip()):
            raise SimulationBug(f"a prompt template starts or ends with a per-episode value: {holes}")
        return cls(pieces, holes)

    def fill(self, values: Mapping[str, str]) -> str:
        parts = [self.pieces[0]]
        for hole, piece in zip(self.holes, self.pieces[1:], strict=True):
            parts.append(values[hole])
            parts.append(piece)
        return "".join(parts)


_SKELETONS: dict[tuple[Any, ...], _Skeleton] = {}


def _render(template: str, native_tools: bool, values: Mapping[str, str | None], **context: Hashable) -> str:
    """``template`` rendered with ``context`` and ``values``.

    Rendering a template is most of what starting an episode's conversations costs, and most of a
    prompt is the same for every episode on the same phone with the same settings (``context``): it is
    rendered once for those as a skeleton, with a hole for each per-episode value (``values``: the start
    time, the persona and goal, the task), which each episode fills in. A template only tests whether
    a value is given (``{% if goal %}``), so a value left out renders as itself, and which values are
    given is part of the skeleton's key.
    """
    given: dict[str, str] = {name: value for name, value in values.items() if value}
    # a value left out is part of the key as itself (None or ""), one given only as given
    shape = tuple((name, True if value else value) for name, value in values.items())
    key = (template, native_tools, tuple(context.items()), shape)
    skeleton = _SKELETONS.get(key)
    if skeleton is None:
        holes = {name: (_HOLE.format(name) if value else value) for name, value in values.items()}
        text = _templates().get_template(template).render(native_tools=native_tools, **context, **holes)
        skeleton = _SKELETONS[key] = _Skeleton.of(text)
    return skeleton.fill(given)
