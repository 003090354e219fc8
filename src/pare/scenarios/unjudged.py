"""Texts whose meaning no judge reads: the solutions' messages no judge check reads, and the world's
reactions decided on free text by a rule alone.

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

A reactive event whose ``if_args`` reads free text (a reply's ``content``) by a matcher alone misjudges
wording its author did not foresee even in runs with a judge model, which it would ask if it had a
``judge`` criterion (:func:`unjudged_events`).

The self-test gate lists both for the runs that make the envelope (the oracle and every passing variant)
and for the scenario's events, apart from its warnings while the library is retrofitted.
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping, Sequence
from typing import Any

from pare.scenarios.checks import linked_entries
from pare.scenarios.model import Scenario
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
