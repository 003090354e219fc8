"""Texts whose meaning nobody reads: the solutions' messages no judge check reads, the text fields they
write into items that no check reads, and the world's reactions decided on free text by a rule alone.

The side-effect envelope (:mod:`pare.scenarios.side_effects`) compares changes by shape: once a solution
emails or messages a person, any text to that person is inside the envelope, a false one too ("Done: I
ordered the GreenLoop bags" when the order holds other bags). So whatever a solution tells a person must
be read for its meaning by some judge check, whose fallback (in the gate, and in runs without a judge
model) and judge model (in runs with one) then reject a wrong text to that person. A text that is part
of the task is read by the goal that wants it; a courtesy message that some solutions send and others do
not is read by an ``optional`` judge check, which holds when nothing is sent (:func:`unread_sends`).
Only emails and messages with words of the assistant's own count: a calendar invitation carries the
event, which state checks read; files sent without a word, and a forward without a note, carry texts the
world wrote, whose choice the goals check. What goes to the user's own address never counts.

A text field the assistant writes into an item (a reminder's description, an event's location, a
contact's notes) that no check reads is unjudged too: "No rush, it stays in the locker until Saturday" in
the description of a right reminder passes (:func:`unread_fields`).

A reactive event whose ``if_args`` reads free text (a reply's ``content``) by a matcher alone misjudges
wording its author did not foresee even in runs with a judge model, which it would ask if it had a
``judge`` criterion (:func:`unjudged_events`).

The self-test gate looks for the first two in the runs that make the envelope (the oracle and every
passing variant) and for the third in the scenario's events; each one found is a breach.
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping, Sequence
from typing import Any

from pare.scenarios.checks import linked_entries
from pare.scenarios.item_text import TEXT_FIELDS
from pare.scenarios.model import ActionPattern, Scenario
from pare.scenarios.stats import FREE_TEXT_FIELDS
from pare.scenarios.told import SENDING_TOOLS, delivery
from pare.sim.log import LogEntry


def unread_sends(scenario: Scenario, log: Sequence[LogEntry], final: Mapping[str, Any]) -> Iterator[str]:
    """One line per email or message the assistant sent in ``log`` (ending in the ``final`` state) to
    someone other than the user, that no judge check of ``scenario`` reads.
    """
    judges = {
        (goal.id, index) for goal in scenario.goals for index, check in enumerate(goal.checks) if check.judge
    }
    read = {
        index
        for key, indexes in linked_entries(scenario, log, final).items()
        if key in judges
        for index in indexes
    }
    own = {str(value).casefold() for value in _own_addresses(final)}

    def app_state(app: str) -> Mapping[str, Any] | None:
        data = final.get(app)
        return data if isinstance(data, Mapping) else None

    for entry in log:
        if entry.actor != "assistant" or f"{entry.app}__{entry.tool}" not in SENDING_TOOLS:
            continue
        written = entry.args.get("content")
        if not (isinstance(written, str) and written.strip()):
            continue  # no words of the assistant's own: files alone, or a forward of the world's email
        sent = delivery(entry, app_state)
        if sent is None or entry.index in read:
            continue
        people = sorted(person for person in sent.people if person.casefold() not in own)
        if people:
            yield (
                f"#{entry.index} {entry.app}__{entry.tool} to {', '.join(people)} is read by no judge check, "
                f"so a false text to them would pass too: add a judge check with 'to: {people[0]}' (with "
                "'optional: true' when telling them is optional) whose criterion and facts say what is true"
            )


def _own_addresses(final: Mapping[str, Any]) -> Iterator[Any]:
    email, messaging = final.get("email"), final.get("messaging")
    if isinstance(email, Mapping) and email.get("user_email"):
        yield email["user_email"]
    if isinstance(messaging, Mapping) and messaging.get("current_user_id"):
        yield messaging["current_user_id"]


def unjudged_events(scenario: Scenario) -> Iterator[str]:
    """One line per reactive event of ``scenario`` whose ``if_args`` read free text with no ``judge``."""
    for event in scenario.events:
        fields = sorted(name for name in event.if_args if name in FREE_TEXT_FIELDS)
        if fields and event.judge is None:
            yield (
                f"event '{event.id}' decides on free text ({', '.join(fields)}) by its rule alone: give it a "
                "'judge' criterion, so that runs with a judge model read the text for its meaning"
            )


_SENDING_APPS = frozenset({"email", "messaging"})
"""Apps whose texts go to people: what they say is :func:`unread_sends`' concern."""


def unread_fields(scenario: Scenario, log: Sequence[LogEntry]) -> Iterator[str]:
    """One line per text field (:data:`TEXT_FIELDS`) the assistant wrote in ``log`` into an item of an app
    that no check of ``scenario`` reads: no state check names the field (or reads ``_text``, or the value
    whole) under that app, no judge check reads it from that app's calls, no action check matches it.
    """
    read = _fields_read(scenario)
    for entry in log:
        if entry.actor != "assistant" or not entry.ok or entry.app in _SENDING_APPS or entry.kind != "write":
            continue
        if "*" in read.get(entry.app, ()):
            continue
        for name, text in _written_texts(entry.args):
            if name not in read.get(entry.app, ()):
                shown = " ".join(text.split())
                shown = shown if len(shown) <= 50 else shown[:47] + "..."
                yield (
                    f"#{entry.index} {entry.app}__{entry.tool} writes '{name}' ({shown!r}), which no check "
                    f"reads, so a wrong {name} would pass: read it (a state check on the field or '_text', "
                    "or an optional judge check on it)"
                )


def _written_texts(args: Mapping[str, Any]) -> Iterator[tuple[str, str]]:
    """The text fields a write's arguments set, also inside ``updates`` (an edit's changes)."""
    updates = args.get("updates")
    for source in (args, updates if isinstance(updates, Mapping) else {}):
        for name in TEXT_FIELDS:
            value = source.get(name)
            if isinstance(value, str) and value.strip():
                yield name, value


def _fields_read(scenario: Scenario) -> dict[str, set[str]]:
    """Per app, the item fields some check reads (``*``: all of them)."""
    read: dict[str, set[str]] = {}
    for goal in scenario.goals:
        for check in (leaf for top in goal.checks for leaf in top.leaves()):  # an any_of's ways read too
            if check.state is not None:
                app = check.state.path.split(".", 1)[0]
                if "value" in check.state.model_fields_set:
                    read.setdefault(app, set()).add("*")
                for key in _where_keys(check.state.where):
                    read.setdefault(app, set()).update(TEXT_FIELDS if key == "_text" else (key,))
            for pattern, fields in _patterns(check):
                for app in _apps(pattern):
                    read.setdefault(app, set()).update(fields)
    return read


def _where_keys(where: Mapping[str, Any]) -> Iterator[str]:
    for key, value in where.items():
        if key == "any_of" and isinstance(value, list):
            for alternative in value:
                if isinstance(alternative, Mapping):
                    yield from _where_keys(alternative)
        else:
            yield key


def _patterns(check: Any) -> Iterator[tuple[ActionPattern, set[str]]]:
    """The action patterns of ``check`` with the argument fields each reads."""
    if check.judge is not None:
        yield check.judge.action, {check.judge.field, *check.judge.action.args}
    for pattern in (check.action, check.no_action):
        if pattern is not None:
            names = set(pattern.args)
            updates = pattern.args.get("updates")
            if isinstance(updates, Mapping):
                names |= {str(name) for name in updates}
            yield pattern, names


def _apps(pattern: ActionPattern) -> set[str]:
    tools = [pattern.tool] if isinstance(pattern.tool, str) else pattern.tool or []
    apps = {tool.split("__", 1)[0] for tool in tools}
    return apps | ({pattern.app} if pattern.app else set())
