"""A person plays the user at the terminal: each turn the phone as the user model would read it, then
a prompt for one action (:mod:`pare.agents.human_input` reads it).

The seat reads lines from an input source (``read``, by default the console's prompt), so a test plays
it with scripted lines and a recording console. Reading blocks the episode on purpose: nothing else
happens while the user decides, as nothing happens while the user model thinks.
"""

from __future__ import annotations

import json
from collections.abc import Callable
from typing import TYPE_CHECKING

from pare.agents.human_input import (
    HELP,
    ArgumentField,
    HumanInputError,
    SeatLeft,
    ToolChoice,
    action_from_fields,
    argument_value,
    menu,
    read_typed_action,
)
from pare.agents.policy import DEFAULT_BUDGET, Action, Ending, TurnBudget, UserPolicy
from pare.env import Environment, ToolResult, UserView

if TYPE_CHECKING:
    from rich.console import Console

HUMAN = "human"
"""The policy name a person in the user's seat is recorded under."""
ON_SCREEN = "\nOn screen: "
TOOLS_HEADING = "\nAvailable tools:"

HELP_TEXT = """\
Each turn you take one action on the screen you are on, as the user simulator does.
  a number       the action of that number in the menu; its arguments are then asked one by one
                 (press Enter to leave an optional one at its default)
  NAME           the action by name (open_app), arguments asked the same way
  NAME {JSON}    the action with its arguments: open_app {"app_name": "email"}
  Action: {...}  the user model's own format: {"action": "open_app", "action_input": {...}}
  wait           do nothing this turn and let time pass
  quit           leave; the episode is not recorded
Answer a proposal with accept_proposal or reject_proposal (each takes an optional reason)."""


def observation_text(previous: ToolResult | None, view: UserView) -> str:
    """What the user model is told this turn, without the list of tools: the result of its last action
    (with what the screen arrived on displays) and the phone now.
    """
    parts = []
    if previous is not None:
        parts.append(f"Observation: {previous.observation()}")
    parts.append(view.render().split(TOOLS_HEADING)[0])
    return "\n\n".join(parts)


def closing_text(ending: Ending, previous: ToolResult | None, notifications: list[str]) -> str:
    """What a person in the user's seat is shown when the session ends: the last action's result, what
    arrived since, and that it is over (as the user model's closing observation says it).
    """
    lines = []
    if previous is not None:
        lines.append(readable(f"Observation: {previous.observation()}"))
    if notifications:
        lines.append("New notifications:")
        lines.extend(f"- {note}" for note in notifications)
    lines.append(ending.text())
    return "\n".join(lines)


def readable(text: str) -> str:
    """``text`` with what the screen displays as indented JSON, for a person to read."""
    head, marker, tail = text.partition(ON_SCREEN)
    if not marker:
        return text
    shown, _, rest = tail.partition("\n")
    try:
        pretty = json.dumps(json.loads(shown), indent=2, ensure_ascii=False)
    except json.JSONDecodeError:
        return text
    return f"{head}{ON_SCREEN}{pretty}" + (f"\n{rest}" if rest else "")


class TerminalUser(UserPolicy):
    """The user played by a person at the terminal (rich), reading their answers from ``read``."""

    name = HUMAN

    def __init__(
        self,
        console: Console,
        read: Callable[[str], str] | None = None,
        *,
        persona: str | None = None,
        goal: str | None = None,
    ) -> None:
        self.console = console
        self.read = read or (lambda prompt: console.input(prompt, markup=False))
        self.persona = persona
        self.goal = goal

    def start(self, env: Environment, budget: TurnBudget = DEFAULT_BUDGET) -> None:
        """Tell the person who they are, what they want, and the rules of the session."""
        from rich.panel import Panel

        from pare.terminal_text import plain_text

        lines = []
        if self.persona:
            lines.append(f"You are: {self.persona}")
        if self.goal:
            lines.append(f"What you want (the assistant is not told): {self.goal}")
        ttl = budget.proposal_ttl_turns
        answer = f"within {ttl} turns" if ttl is not None else "before the session ends"
        lines.append(
            f"The session lasts at most {budget.max_turns} turns; you take {budget.user_steps} action(s) a "
            f"turn. A proposal from the assistant must be answered {answer}. Type 'help' for how to act."
        )
        self.console.print(Panel(plain_text("\n".join(lines)), title="You are the user"))

    async def step(self, view: UserView, previous: ToolResult | None) -> Action:
        """Show the phone and ask until the person gives an action valid on this screen."""
        self._show(view, previous)
        while True:
            typed = self._ask("action> ")
            if typed.strip().lower() in HELP:
                self.console.print(HELP_TEXT, markup=False, highlight=False)
                continue
            try:
                chosen = read_typed_action(typed, view)
                if isinstance(chosen, ToolChoice):
                    chosen = self._arguments(view, chosen)
            except HumanInputError as error:
                self._complain(str(error))
                continue
            return chosen

    def finish(self, ending: Ending, previous: ToolResult | None, notifications: list[str]) -> str | None:
        """Show the result of the last action, what arrived since, and that the session is over."""
        from pare.terminal_text import plain_text

        self.console.print(plain_text(closing_text(ending, previous, notifications)))
        return None

    # -- showing and asking --------------------------------------------------------------------------------
    def _show(self, view: UserView, previous: ToolResult | None) -> None:
        from rich.panel import Panel
        from rich.table import Table

        from pare.terminal_text import plain_text

        title = f"Turn {view.turn.turn} of {view.turn.of}" if view.turn is not None else "Your phone"
        self.console.rule(title)
        self.console.print(plain_text(readable(observation_text(previous, view))))
        if view.pending_proposal:
            self.console.print(
                Panel(
                    plain_text(view.pending_proposal), title="The assistant proposes", border_style="yellow"
                )
            )
        table = Table(show_header=False, box=None, pad_edge=False)
        for number, tool in enumerate(menu(view), start=1):
            table.add_row(str(number), plain_text(tool.spec.signature), plain_text(tool.spec.summary, "dim"))
        self.console.print(table)

    def _arguments(self, view: UserView, choice: ToolChoice) -> Action:
        typed: dict[str, str] = {}
        for field in choice.fields:
            typed[field.name] = self._argument(field)
        return action_from_fields(view, choice.tool.name, typed)

    def _argument(self, field: ArgumentField) -> str:
        """Ask for one argument until what is typed can be used (or is left empty when optional)."""
        optional = "" if field.required else f", Enter for {field.default!r}"
        prompt = f"  {field.name} ({field.type_text}{optional}): "
        while True:
            typed = self._ask(prompt)
            try:
                argument_value(field, typed)
            except HumanInputError as error:
                self._complain(str(error))
                continue
            return typed

    def _ask(self, prompt: str) -> str:
        try:
            return self.read(prompt)
        except EOFError:  # the input ended (Ctrl-D, or a script ran out): the person has left
            raise SeatLeft from None

    def _complain(self, message: str) -> None:
        from pare.terminal_text import plain_text

        self.console.print(plain_text(message, "red"))
