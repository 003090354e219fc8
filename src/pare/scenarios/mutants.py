"""Mutants and rewrites of a scenario's oracle: the near-misses and the equivalent solutions the gate
writes itself, the way mutation testing judges a test suite.

A *mutant* changes one thing in the oracle assistant's work that the story does not allow, and the checks
must fail it: the person written to, a day or an hour, an action left out, an email kept as a draft, a
second write to another item of the seed, a quantity or price, an attached file. A *rewrite* changes how
the work is done but not what it does, and the checks must pass it: two independent actions the other way
round, a time in the text written another way, the message sent in two halves.

Both are generated from the oracle's interventions and the seed alone, deterministically: the same
scenario gives the same mutants, in the same order, with the same names, and a choice among several
candidates (which other person, which other file) is made by a random generator seeded by the scenario's
id and the mutant's name. A name reads ``<operator>:<where>``, ``where`` being the action (``1.2``: the
second action of the first intervention) and, when it matters, the argument and the change
(``shift_time:1.1:+1d``). A scenario declares a mutant equivalent to the oracle, with a reason, under
that name (``equivalent_mutants``).

Only the assistant's writes are mutated: what a read asks changes nothing the checks may judge.
"""

from __future__ import annotations

import random
import re
from collections.abc import Callable, Iterator, Mapping
from dataclasses import dataclass
from datetime import datetime, timedelta
from functools import cached_property
from typing import Any, Literal

from pare.scenarios import mutant_seed as seed_reading
from pare.scenarios.leaves import strings
from pare.scenarios.model import (
    MUTANT_OPERATORS,
    REWRITE_OPERATORS,
    Intervention,
    OracleAction,
    Scenario,
    Solution,
)
from pare.scenarios.times import TimeFormatError, parse_time
from pare.scenarios.validation import ToolCatalog

PER_OPERATOR = 3
"""At most this many mutants (or rewrites) of one operator per scenario: the first places it applies to.
Enough to show what an operator finds; the gate stays fast on the whole library."""

_DAY = re.compile(r"^day(?:([+-])(\d+))?\s+(\d{1,2}):(\d{2})(?::(\d{2}))?$")
_CLOCK = re.compile(r"(?<![\d:.])([01]?\d|2[0-3]):([0-5]\d)(?![\d:])(?!\s*(?:[aApP]\.?[mM]))")
_SENTENCE_END = re.compile(r"(?<=[.!?])\s+(?=\S)")
_PEOPLE_ARGS = frozenset({"user_id", "user_ids", "recipients", "attendees", "cc", "bcc", "to"})
"""Arguments that name people: ``swap_person`` reads them, ``swap_item`` leaves them alone."""
_ATTACHMENT_ARGS = frozenset({"attachments", "attachment"})
_SEND_TOOLS = frozenset(
    {
        "email__send_email",
        "email__reply_to_email",
        "email__forward_email",
        "messaging__send_message",
        "messaging__send_message_to_group_conversation",
    }
)
"""Tools that send a text to people: the ones ``split_message`` sends twice."""
_HOUR_FREE_APPS = frozenset({"reminder"})
"""Apps whose times are not shifted by an hour: a reminder's hour is the assistant's choice within the
part of the day the story names (the evening before, Thursday morning), so an hour later is often as right;
its day is shifted like any other time."""
_SPLIT_FIELDS = ("content", "body", "message", "text")

Expect = Literal["fail", "pass"]


@dataclass(frozen=True, slots=True)
class Mutant:
    """One generated solution: a mutant that must fail, or a rewrite that must pass."""

    name: str
    """``<operator>:<where>``, stable for the scenario (see the module's docstring)."""
    operator: str
    expect: Expect
    what: str
    """What was changed, for reports."""
    solution: Solution
    waits_for: tuple[str, str] | None = None
    """For a proposal moved earlier: the event it no longer waits for and the proposal's text, so that a
    run where the event came first anyway (nothing moved) is told apart."""

    @property
    def is_rewrite(self) -> bool:
        """Whether the checks must pass it (a rewrite) rather than fail it (a mutant)."""
        return self.expect == "pass"


def mutants(scenario: Scenario) -> list[Mutant]:
    """The mutants of ``scenario``'s oracle that its checks must fail, by operator in a fixed order."""
    return _generate(scenario, MUTANT_OPERATORS, "fail")


def rewrites(scenario: Scenario) -> list[Mutant]:
    """The rewrites of ``scenario``'s oracle that its checks must pass, by operator in a fixed order."""
    return _generate(scenario, REWRITE_OPERATORS, "pass")


# -- generation ---------------------------------------------------------------------------------------
@dataclass(frozen=True, slots=True)
class _Edit:
    """One operator's change: where, what it did, and the interventions it gives."""

    where: str
    what: str
    interventions: tuple[Intervention, ...]
    waits_for: tuple[str, str] | None = None


Operator = Callable[["_Oracle"], Iterator[_Edit]]


def _generate(scenario: Scenario, names: tuple[str, ...], expect: Expect) -> list[Mutant]:
    oracle = _Oracle(scenario)
    found: list[Mutant] = []
    for operator in names:
        seen: set[str] = set()
        for edit in _OPERATORS[operator](oracle):
            name = f"{operator}:{edit.where}"
            if name in seen:
                continue
            seen.add(name)
            solution = Solution(name, tuple(scenario.oracle.user), edit.interventions)
            found.append(Mutant(name, operator, expect, edit.what, solution, edit.waits_for))
            if len(seen) == PER_OPERATOR:
                break
    return found


class _Oracle:
    """A scenario's oracle and seed, read for what the operators need."""

    def __init__(self, scenario: Scenario) -> None:
        self.scenario = scenario
        self.interventions = tuple(scenario.oracle.interventions)
        self.catalog = catalog = ToolCatalog(scenario.all_apps)
        self.writes = [
            (i, j, action)
            for i, intervention in enumerate(self.interventions)
            for j, action in enumerate(intervention.actions)
            if (spec := catalog.flat.get(action.tool)) is not None and spec.kind == "write"
        ]
        """The assistant's writes, with their intervention's and their own index."""
        self.people = seed_reading.people(scenario.seed)
        self.files = seed_reading.files(scenario.seed)
        passing = scenario.right_solutions()
        self.used = frozenset(
            text
            for name in passing
            for intervention in scenario.solution(name).interventions
            for action in intervention.actions
            for text in strings(action.args)
        )
        """Every string the actions of the oracle and of the passing variants give: the items (and files)
        a right solution is about; the others are distractors."""

        self._app_seeds: dict[str, tuple[Mapping[str, Any], dict[str, set[str]]]] = {}
        self.own_address = str(scenario.seed.get("email", {}).get("user_email", "")).lower()
        seeded = scenario.seed.get("email", {}).get("emails", []) or []
        self.emails_with_event: dict[str, tuple[Mapping[str, Any], str | None]] = {
            str(email.get("email_id")): (email, None) for email in seeded if isinstance(email, Mapping)
        }
        """The emails known before the run, each with the event that brings it (``None``: the seed's)."""
        for event in scenario.events:
            if event.tool == "email__receive_email":
                self.emails_with_event[str(event.args.get("email_id"))] = (event.args, event.id)
        self.emails = {email_id: email for email_id, (email, _) in self.emails_with_event.items()}

    @cached_property
    def world_texts(self) -> tuple[str, ...]:
        """The texts of the seed and of the events that name a number: where the world offers slots."""
        scenario = self.scenario
        found = [
            *seed_reading.texts(scenario.seed),
            *(t for e in scenario.events for t in seed_reading.texts(e.args)),
        ]
        return tuple(text for text in dict.fromkeys(found) if any(char.isdigit() for char in text))

    def app_seed(self, app: str) -> tuple[Mapping[str, Any], dict[str, set[str]]]:
        """``app``'s seed and where each of its strings is kept (read once per app)."""
        if app not in self._app_seeds:
            seed = self.scenario.seed.get(app, {})
            self._app_seeds[app] = (seed, seed_reading.places(seed))
        return self._app_seeds[app]

    def rng(self, name: str) -> random.Random:
        """The generator for the choice a mutant called ``name`` makes: the same on every run."""
        return random.Random(f"{self.scenario.id}/{name}")

    def replaced(self, i: int, j: int, actions: list[OracleAction]) -> tuple[Intervention, ...]:
        """The interventions with action ``j`` of intervention ``i`` replaced by ``actions``."""
        intervention = self.interventions[i]
        changed = [*intervention.actions[:j], *actions, *intervention.actions[j + 1 :]]
        return self.with_actions(i, changed)

    def with_actions(self, i: int, actions: list[OracleAction]) -> tuple[Intervention, ...]:
        """The interventions with intervention ``i``'s actions replaced by ``actions``."""
        changed = self.interventions[i].model_copy(update={"actions": actions})
        return (*self.interventions[:i], changed, *self.interventions[i + 1 :])


def _where(i: int, j: int, *parts: str) -> str:
    return ":".join([f"{i + 1}.{j + 1}", *parts])


def _with_args(action: OracleAction, args: dict[str, Any]) -> OracleAction:
    return action.model_copy(update={"args": args})


def _is_reference(value: Any) -> bool:
    return isinstance(value, str) and "${" in value


# -- the mutants --------------------------------------------------------------------------------------
def _drop_action(oracle: _Oracle) -> Iterator[_Edit]:
    """Each write left out."""
    for i, j, action in oracle.writes:
        yield _Edit(_where(i, j), f"left out {action.tool}", oracle.replaced(i, j, []))


def _send_as_draft(oracle: _Oracle) -> Iterator[_Edit]:
    """An email saved as a draft instead of sent: a new email, or a reply to an email of the seed or of an
    event (the draft addressed to its sender, with its subject).
    """
    for i, j, action in oracle.writes:
        args = dict(action.args)
        if action.tool == "email__reply_to_email":
            replied = oracle.emails.get(str(args.pop("email_id", "")))
            if replied is None:
                continue
            args = {
                "recipients": [replied.get("sender")],
                "subject": f"Re: {replied.get('subject', '')}",
                **args,
            }
        elif action.tool != "email__send_email":
            continue
        draft = OracleAction(tool="email__save_draft", args=args)
        yield _Edit(_where(i, j), f"{action.tool} saved as a draft, not sent", oracle.replaced(i, j, [draft]))


def _swap_person(oracle: _Oracle) -> Iterator[_Edit]:
    """The person a write names (recipient, attendee, conversation partner) swapped for another person of
    the seed, of the same form (an address for an address, a user id for a user id, a name for a name);
    the first person of each argument that has another to swap with.
    """
    swapped: set[tuple[int, int, str]] = set()
    for i, j, action, key, values, position in _listed(oracle, _PEOPLE_ARGS):
        person = values[position]
        if (i, j, key) in swapped or not isinstance(person, str) or _is_reference(person):
            continue
        pool = next((pool for pool in oracle.people if person in pool), None)
        others = sorted(p for p in pool or () if p not in values)
        if not others:
            continue
        where = _where(i, j, key)
        other = oracle.rng(f"swap_person:{where}").choice(others)
        what = f"{action.tool} {key}: {person} -> {other}"
        yield _Edit(where, what, oracle.replaced(i, j, [_swapped(action, key, position, other)]))
        swapped.add((i, j, key))


def _listed(
    oracle: _Oracle, names: frozenset[str]
) -> Iterator[tuple[int, int, OracleAction, str, list[Any], int]]:
    """Each value of the oracle's writes' arguments named in ``names``, a list's items one by one:
    ``(i, j, action, key, values, position)``, ``values`` being the argument as a list.
    """
    for i, j, action in oracle.writes:
        for key in sorted(action.args):
            if key in names:
                value = action.args[key]
                values = value if isinstance(value, list) else [value]
                for position in range(len(values)):
                    yield i, j, action, key, values, position


def _swapped(action: OracleAction, key: str, position: int, other: Any) -> OracleAction:
    """``action`` with the value at ``position`` of its argument ``key`` (a list, or one value) replaced."""
    value = action.args[key]
    if isinstance(value, list):
        other = [*value[:position], other, *value[position + 1 :]]
    return _with_args(action, {**action.args, key: other})


def _shift_time(oracle: _Oracle) -> Iterator[_Edit]:
    """Every time a write gives (a start and its end together) a day later, then an hour later: later,
    not earlier, since a story that says "by" or "before" may allow an earlier time.
    """
    for shift, label in ((timedelta(days=1), "+1d"), (timedelta(hours=1), "+1h")):
        for i, j, action in oracle.writes:
            if label == "+1h" and action.tool.partition("__")[0] in _HOUR_FREE_APPS:
                continue
            shifted, changed = _shifted(action.args, shift)
            if changed:
                what = f"{action.tool} {', '.join(changed)} {label}"
                yield _Edit(_where(i, j, label), what, oracle.replaced(i, j, [_with_args(action, shifted)]))


def _shift_text_time(oracle: _Oracle) -> Iterator[_Edit]:
    """The clock times in a sent or written text an hour later, said as people say them ("half seven in
    the evening" where the text had 18:30): the wrong time in words the reader must read too.
    """
    for i, j, action, key, value in _texts_of(oracle):
        said = [_spoken(match, later=1) for match in _CLOCK.finditer(value)]
        if not said:
            continue
        args = {**action.args, key: _CLOCK.sub(lambda match: _spoken(match, later=1), value)}
        what = f"{action.tool} {key} with its times an hour later, as " + ", ".join(said)
        yield _Edit(_where(i, j, key), what, oracle.replaced(i, j, [_with_args(action, args)]))


def _shifted(value: Any, shift: timedelta) -> tuple[Any, list[str]]:
    """``value`` with every time in it moved by ``shift``, and the keys of the times moved."""
    if isinstance(value, Mapping):
        out: dict[str, Any] = {}
        moved: list[str] = []
        for key, item in value.items():
            if isinstance(item, str) and (later := _later(item, shift)) is not None:
                out[key], moved = later, [*moved, str(key)]
            else:
                out[key], inner = _shifted(item, shift)
                moved.extend(inner)
        return out, moved
    return value, []


def _later(text: str, shift: timedelta) -> str | None:
    """``text`` (a time as scenarios write them) ``shift`` later, or ``None`` when it is no time."""
    day = _DAY.match(text.strip())
    if day:
        sign, days, hour, minute, second = day.groups()
        offset = int(days or 0) * (-1 if sign == "-" else 1)
        moment = datetime(2000, 1, 10, int(hour), int(minute), int(second or 0)) + shift
        offset += (moment.date() - datetime(2000, 1, 10).date()).days
        clock = moment.strftime("%H:%M:%S" if second else "%H:%M")
        return f"day{offset:+d} {clock}" if offset else f"day {clock}"
    if len(text) < 10 or not text[:4].isdigit():
        return None
    try:
        moment = datetime.fromisoformat(text.replace("Z", "+00:00"))
    except ValueError:
        return None
    if len(text) == 10:  # a date alone: shifted by days only (an hour later is the same date)
        return (moment + timedelta(days=shift.days)).date().isoformat() if shift.days else None
    later = (moment + shift).isoformat()
    return later.replace("+00:00", "Z") if text.endswith("Z") else later


def _extra_write(oracle: _Oracle) -> Iterator[_Edit]:
    """A write done as asked, then done again to a distractor, an item of the seed that no right solution
    (the oracle, a passing variant) touches (another email, event, product, flat): the second write is one
    no goal asked for.
    """
    for i, j, action in oracle.writes:
        for key, other in _other_items(oracle, i, j, action, "extra_write"):
            twin = OracleAction(tool=action.tool, args={**action.args, key: other})
            what = f"{action.tool} also on {key} {other}"
            yield _Edit(_where(i, j, key), what, oracle.replaced(i, j, [action, twin]))


def _swap_item(oracle: _Oracle) -> Iterator[_Edit]:
    """A write done to a distractor instead of the item asked (another email, event, product, flat of the
    seed that no right solution touches).
    """
    for i, j, action in oracle.writes:
        for key, other in _other_items(oracle, i, j, action, "swap_item"):
            args = {**action.args, key: other}
            what = f"{action.tool} {key}: {action.args[key]} -> {other}"
            yield _Edit(_where(i, j, key), what, oracle.replaced(i, j, [_with_args(action, args)]))


def _other_items(
    oracle: _Oracle, i: int, j: int, action: OracleAction, operator: str
) -> Iterator[tuple[str, str]]:
    """For each argument of ``action`` naming a seed item by its id: the argument and another item's id of
    the same kind in the same app's seed, chosen by the mutant's generator.
    """
    for key, others in _distractors(oracle, action):
        yield key, oracle.rng(f"{operator}:{_where(i, j, key)}").choice(others)


def _distractors(oracle: _Oracle, action: OracleAction) -> Iterator[tuple[str, list[str]]]:
    """For each argument of ``action`` naming a seed item by its id: the argument and the ids of the
    distractors of its kind, items of the same app's seed that no right solution touches; those kept where
    the item is, if any (a saved flat for a saved flat: removing a flat that is not saved changes nothing).
    """
    _, places = oracle.app_seed(action.tool.partition("__")[0])
    for key in sorted(action.args):
        value = action.args[key]
        if not key.endswith("_id") or key in _PEOPLE_ARGS or not isinstance(value, str):
            continue
        ids = {text for text, where in places.items() if any(place.endswith(f".{key}") for place in where)}
        if value not in ids:  # an item the story brings later: where its kind is kept is not in the seed
            continue
        others = sorted(ids - oracle.used)
        alike = [other for other in others if places[other] >= places[value]]
        if others:
            yield key, alike or others


def _change_number(oracle: _Oracle) -> Iterator[_Edit]:
    """A quantity, price or size a write gives, changed: a whole number one more, another number a tenth
    more.
    """
    for i, j, action in oracle.writes:
        for key in sorted(action.args):
            value = action.args[key]
            if isinstance(value, bool) or not isinstance(value, int | float):
                continue
            other = value + 1 if isinstance(value, int) else round(value * 1.1 + 0.01, 2)
            args = {**action.args, key: other}
            what = f"{action.tool} {key}: {value} -> {other}"
            yield _Edit(_where(i, j, key), what, oracle.replaced(i, j, [_with_args(action, args)]))


def _swap_file(oracle: _Oracle) -> Iterator[_Edit]:
    """An attached file swapped for another file of the seed with other content (one of the same kind, by
    its extension, when there is one).
    """
    for i, j, action, key, values, position in _listed(oracle, _ATTACHMENT_ARGS):
        path = values[position]
        if (
            not isinstance(path, str)
            or _is_reference(path)
            or seed_reading.normal_path(path) not in oracle.files
        ):
            continue
        attached = {
            oracle.files[seed_reading.normal_path(p)]
            for p in values
            if seed_reading.normal_path(str(p)) in oracle.files
        }
        # another content: a copy of the same file under another path is the same file
        others = sorted(other for other, content in oracle.files.items() if content not in attached)
        same_kind = [p for p in others if p.rpartition(".")[2] == path.rpartition(".")[2]]
        if not others:
            continue
        where = _where(i, j, f"{key}[{position}]")
        other = oracle.rng(f"swap_file:{where}").choice(same_kind or others)
        what = f"{action.tool} {key}: {path} -> {other}"
        yield _Edit(where, what, oracle.replaced(i, j, [_swapped(action, key, position, other)]))


def _other_slot(oracle: _Oracle) -> Iterator[_Edit]:
    """The time a write gives moved to another slot the world offers: when a text of the seed or of an
    event names the oracle's time among others ("Tuesday 14:00 or Thursday at 10"), one of the others; when
    it names only clock times, another of them on the same day. The start and its end move together.
    """
    start = oracle.scenario.start
    used = {moment for text in oracle.used if (moment := _moment(text, start)) is not None}
    # what the seed's items are already at is no slot on offer ("we have to move your 08:00")
    used |= {moment for text in strings(oracle.scenario.seed) if (moment := _moment(text, start)) is not None}
    for i, j, action in oracle.writes:
        found = _first_time(action.args, start)
        if found is None:
            continue
        moment = found
        others = {slot for slot in _slots_beside(oracle, moment) if slot not in used}
        others -= {moment + timedelta(days=1), moment + timedelta(hours=1)}  # shift_time's own
        if not others:
            continue
        other = oracle.rng(f"other_slot:{_where(i, j)}").choice(sorted(others))
        shifted, changed = _shifted(action.args, other - moment)
        label = f"{other:%a %d %b %H:%M}"
        what = f"{action.tool} {', '.join(changed)} moved to another offered slot, {label}"
        yield _Edit(_where(i, j), what, oracle.replaced(i, j, [_with_args(action, shifted)]))


def _slots_beside(oracle: _Oracle, moment: datetime) -> set[datetime]:
    """The other slots offered by the world's texts that offer ``moment``; failing those, its day at the
    other clock times of the texts that name its clock time.
    """
    slots: set[datetime] = set()
    clocks: set[tuple[int, int]] = set()
    for text in oracle.world_texts:
        offered = seed_reading.offered_slots(text, oracle.scenario.start)
        if moment in {slot for slot, _ in offered}:
            slots |= {slot for slot, single in offered if single and slot != moment}
        named = seed_reading.offered_clocks(text, oracle.scenario.start)
        if (moment.hour, moment.minute) in named:
            clocks |= {clock for clock in named if clock != (moment.hour, moment.minute)}
    if slots:
        return slots
    return {moment.replace(hour=hour, minute=minute) for hour, minute in clocks}


def _first_time(args: Mapping[str, Any], start: datetime) -> datetime | None:
    """The time a write is about: its start (or due time, or ride time) when it gives several."""
    times = [(key, moment) for key, text in _flat_strings(args) if (moment := _moment(text, start))]
    if not times:
        return None
    starting = [moment for key, moment in times if "start" in key or "due" in key or "ride" in key]
    return (starting or [moment for _, moment in times])[0]


def _flat_strings(value: Any, key: str = "") -> Iterator[tuple[str, str]]:
    """Each string of ``value`` with the key it is under, nested mappings read through."""
    if isinstance(value, str):
        yield key, value
    elif isinstance(value, Mapping):
        for name in sorted(value):
            yield from _flat_strings(value[name], str(name))


def _moment(text: str, start: datetime) -> datetime | None:
    """``text`` as the moment it names (``day+2 09:00``, an ISO time with its clock), or ``None``."""
    if _later(text, timedelta()) is None or len(text.strip()) == 10:
        return None
    try:
        return parse_time(text, start)
    except TimeFormatError:
        return None


def _similar_item(oracle: _Oracle) -> Iterator[_Edit]:
    """A write done on the distractor most like the item asked (the same product in another size, the
    flat next door): of the seed's items of the same kind that no right solution touches, the one whose
    description shares the most words with the item's.
    """
    for i, j, action in oracle.writes:
        seed = oracle.scenario.seed.get(action.tool.partition("__")[0], {})
        for key, others in _distractors(oracle, action):
            value = action.args[key]
            own = seed_reading.description_words(seed, key, value)
            alike = {
                other: seed_reading.likeness(own, seed_reading.description_words(seed, key, other))
                for other in others
            }
            best = max(alike.values(), default=0.0)
            if best <= 0:
                continue
            nearest = sorted(other for other, score in alike.items() if score == best)
            other = oracle.rng(f"similar_item:{_where(i, j, key)}").choice(nearest)
            if other == oracle.rng(f"swap_item:{_where(i, j, key)}").choice(others):
                continue  # the distractor swap_item already chose: the same mutant again
            args = {**action.args, key: other}
            what = f"{action.tool} {key}: {value} -> {other}, the most alike in the seed"
            yield _Edit(_where(i, j, key), what, oracle.replaced(i, j, [_with_args(action, args)]))


def _early_proposal(oracle: _Oracle) -> Iterator[_Edit]:
    """An intervention that waits for an event (the message that asks, the news that makes it needed)
    proposed at once instead, before the fact that justifies it has arrived. Where the event comes before
    the assistant's next turn anyway (a reply a minute after the question), the proposal is not earlier
    after all: the gate counts such a mutant as stillborn.
    """
    start = oracle.scenario.start
    events = {event.id: event for event in oracle.scenario.events}
    for i, intervention in enumerate(oracle.interventions):
        event = events.get(intervention.when.event or "") if intervention.when else None
        if event is None:
            continue
        if event.at is not None and parse_time(event.at, start) <= start:
            continue  # the fact is there from the start: proposing at once is what the oracle does
        early = intervention.model_copy(update={"when": None})
        what = f"intervention {i + 1} proposed at once, before event '{event.id}'"
        changed = (*oracle.interventions[:i], early, *oracle.interventions[i + 1 :])
        yield _Edit(f"{i + 1}", what, changed, (event.id, intervention.proposal))


# -- the rewrites -------------------------------------------------------------------------------------
def _reorder(oracle: _Oracle) -> Iterator[_Edit]:
    """Two neighbouring writes of an intervention the other way round, when neither needs the other: the
    same tool on different items, or different apps, with no result of the first used by the second and
    no value in common (a file the first makes and the second sends).
    """
    for i, intervention in enumerate(oracle.interventions):
        actions = list(intervention.actions)
        writes = {j for wi, j, _ in oracle.writes if wi == i}
        for j in range(len(actions) - 1):
            first, second = actions[j], actions[j + 1]
            if j in writes and j + 1 in writes and _independent(first, second):
                swapped = [*actions[:j], second, first, *actions[j + 2 :]]
                what = f"{first.tool} and {second.tool} the other way round"
                yield _Edit(f"{i + 1}.{j + 1}", what, oracle.with_actions(i, swapped))
                break


def _independent(first: OracleAction, second: OracleAction) -> bool:
    if first.id is not None and f"${{{first.id}" in repr(second.args):
        return False
    same_app = first.tool.partition("__")[0] == second.tool.partition("__")[0]
    if same_app and first.tool != second.tool:
        return False  # add to the cart, then check out: the app's order is the task's
    shared = set(strings(first.args)) & set(strings(second.args))
    return not {value for value in shared if len(value) >= 4 and not value.isdigit()}


_TEXT_FIELDS = (*_SPLIT_FIELDS, "description", "title", "subject", "notes")


def _texts_of(oracle: _Oracle) -> Iterator[tuple[int, int, OracleAction, str, str]]:
    """Each text a write gives: ``(i, j, action, key, text)``."""
    for i, j, action in oracle.writes:
        for key in sorted(action.args):
            value = action.args[key]
            if key in _TEXT_FIELDS and isinstance(value, str):
                yield i, j, action, key, value


def _time_phrasing(oracle: _Oracle) -> Iterator[_Edit]:
    """The clock times in a sent or written text in the 12-hour form (09:30 as 9:30am, 18:00 as 6pm), then
    in words (9.30 in the morning, 6 in the evening; a range stays in the 12-hour form).
    """
    for form, phrase in (("", _twelve_hour), ("words", _in_words), ("spoken", _spoken)):
        for i, j, action, key, value in _texts_of(oracle):
            rephrased = _CLOCK.sub(phrase, value)
            if rephrased != value:
                args = {**action.args, key: rephrased}
                what = f"{action.tool} {key} with its times as " + ", ".join(
                    phrase(m) for m in _CLOCK.finditer(value)
                )
                where = _where(i, j, key, *([form] if form else []))
                yield _Edit(where, what, oracle.replaced(i, j, [_with_args(action, args)]))


_SPOKEN_HOURS = ("twelve", "one", "two", "three", "four", "five", "six", "seven", "eight", "nine", "ten",
                 "eleven")  # fmt: skip
_SPOKEN_MINUTES = {5: "five", 10: "ten", 15: "quarter", 20: "twenty", 25: "twenty-five", 30: "half"}


def _spoken(match: re.Match[str], *, later: int = 0) -> str:
    """A clock time (``later`` hours on) as said in Britain: "half seven in the evening", "quarter to nine
    in the morning", "ten past six in the evening", "seven o'clock in the evening" (a range's ends, and
    minutes off the five, stay in the 12-hour form).
    """
    hour, minute = (int(match.group(1)) + later) % 24, int(match.group(2))
    if _in_a_range(match) or minute % 5:
        return _twelve_hour(match, later=later)
    if (hour, minute) in ((12, 0), (0, 0)):
        return "12 noon" if hour else "midnight"
    part = _part_of_day(hour)
    if minute == 0:
        return f"{_SPOKEN_HOURS[hour % 12]} o'clock {part}"
    if minute == 30:
        return f"half {_SPOKEN_HOURS[hour % 12]} {part}"
    if minute < 30:
        return f"{_SPOKEN_MINUTES[minute]} past {_SPOKEN_HOURS[hour % 12]} {part}"
    return f"{_SPOKEN_MINUTES[60 - minute]} to {_SPOKEN_HOURS[(hour + 1) % 12]} {part}"


def _in_a_range(match: re.Match[str]) -> bool:
    """Whether the time ``match`` found is one end of a range ("17:00-19:00")."""
    text = match.string
    after = text[match.end() : match.end() + 2].lstrip()[:1]
    before = text[max(0, match.start() - 2) : match.start()].rstrip()[-1:]
    return after in ("-", "\u2013") or before in ("-", "\u2013")


def _part_of_day(hour: int) -> str:
    """How a time's part of the day is said after it."""
    if hour < 5 or hour >= 22:
        return "at night"
    if hour < 12:
        return "in the morning"
    return "in the afternoon" if hour < 18 else "in the evening"


def _twelve_hour(match: re.Match[str], *, later: int = 0) -> str:
    hour, minute = (int(match.group(1)) + later) % 24, int(match.group(2))
    suffix = "am" if hour < 12 else "pm"
    clock = hour % 12 or 12
    return f"{clock}{suffix}" if minute == 0 else f"{clock}:{minute:02d}{suffix}"


def _in_words(match: re.Match[str]) -> str:
    """A clock time as said: "6 in the evening", "9.30 in the morning", "12 noon"."""
    if _in_a_range(match):
        return _twelve_hour(match)  # one end of a range: "5pm-7pm" reads better than words
    hour, minute = int(match.group(1)), int(match.group(2))
    if (hour, minute) == (12, 0):
        return "12 noon"
    part = _part_of_day(hour)
    clock = hour % 12 or 12
    return f"{clock} {part}" if minute == 0 else f"{clock}.{minute:02d} {part}"


_MONTHS = (
    "January",
    "February",
    "March",
    "April",
    "May",
    "June",
    "July",
    "August",
    "September",
    "October",
    "November",
    "December",
)
_MONTH = "|".join(_MONTHS)
_ISO_DATE = re.compile(r"(?<![\d-])(\d{4})-(\d{2})-(\d{2})(?![\d-])")
_DAY_MONTH = re.compile(rf"\b(\d{{1,2}})(?:st|nd|rd|th)?\s+({_MONTH})\b")
_MONTH_DAY = re.compile(rf"\b({_MONTH})\s+(\d{{1,2}})(?:st|nd|rd|th)?\b(?!:)")


def _date_phrasing(oracle: _Oracle) -> Iterator[_Edit]:
    """The dates in a sent or written text in another common form: 2026-06-04 as 4 June 2026, 4 June as
    June 4th, June 4 as 4 June.
    """
    for i, j, action, key, value in _texts_of(oracle):
        rephrased = _other_date_forms(value)
        if rephrased != value:
            args = {**action.args, key: rephrased}
            what = f"{action.tool} {key} with its dates written another way"
            yield _Edit(_where(i, j, key), what, oracle.replaced(i, j, [_with_args(action, args)]))


def _other_date_forms(text: str) -> str:
    def iso(match: re.Match[str]) -> str:
        year, month, day = (int(part) for part in match.groups())
        if not 1 <= month <= 12 or not 1 <= day <= 31:
            return match.group(0)
        return f"{day} {_MONTHS[month - 1]} {year}"

    def day_month(match: re.Match[str]) -> str:
        day = int(match.group(1))
        return f"{match.group(2)} {day}{_ordinal(day)}"

    def month_day(match: re.Match[str]) -> str:
        return f"{int(match.group(2))} {match.group(1)}"

    # one pass per form, each on the text the one before left: a date is rewritten once
    marked = _ISO_DATE.sub(lambda m: "\0" + iso(m) + "\0", text)
    pieces = marked.split("\0")
    out = []
    for index, piece in enumerate(pieces):
        if index % 2:  # an ISO date just rewritten
            out.append(piece)
        elif _DAY_MONTH.search(piece):
            out.append(_DAY_MONTH.sub(day_month, piece))
        else:
            out.append(_MONTH_DAY.sub(month_day, piece))
    return "".join(out)


def _ordinal(day: int) -> str:
    if 10 <= day % 100 <= 20:
        return "th"
    return {1: "st", 2: "nd", 3: "rd"}.get(day % 10, "th")


def _split_message(oracle: _Oracle) -> Iterator[_Edit]:
    """A text sent in two messages to the same people: the first half with what is attached, then the
    second half alone.
    """
    for i, j, action in oracle.writes:
        if action.tool not in _SEND_TOOLS:
            continue
        key = next((k for k in _SPLIT_FIELDS if isinstance(action.args.get(k), str)), None)
        if key is None:
            continue
        halves = _halves(action.args[key])
        if halves is None:
            continue
        first = _with_args(action, {**action.args, key: halves[0]})
        rest = {k: v for k, v in action.args.items() if k not in _ATTACHMENT_ARGS}
        second = OracleAction(tool=action.tool, args={**rest, key: halves[1]})
        what = f"{action.tool} sent in two messages"
        yield _Edit(_where(i, j), what, oracle.replaced(i, j, [first, second]))


def _halves(text: str) -> tuple[str, str] | None:
    """``text`` cut at the sentence end nearest its middle, or ``None`` for a single sentence."""
    stripped = text.strip()
    cuts = [match.start() for match in _SENTENCE_END.finditer(stripped)]
    if not cuts:
        return None
    cut = min(cuts, key=lambda at: abs(at - len(stripped) / 2))
    return stripped[:cut].strip(), stripped[cut:].strip()


def _reply_as_new(oracle: _Oracle) -> Iterator[_Edit]:
    """A reply sent as a new email to the same person, with the reply's subject ("Re: ...")."""
    for i, j, action in oracle.writes:
        if action.tool != "email__reply_to_email":
            continue
        replied = oracle.emails.get(str(action.args.get("email_id", "")))
        if replied is None:
            continue
        sender = str(replied.get("sender", ""))
        recipients = (
            [str(r) for r in replied.get("recipients", []) or []]
            if sender.lower() == oracle.own_address
            else [sender]
        )
        subject = str(replied.get("subject", ""))
        args = {
            "recipients": recipients,
            "subject": subject if subject.lower().startswith("re:") else f"Re: {subject}",
            **{k: v for k, v in action.args.items() if k != "email_id"},
        }
        what = f"the reply to {action.args['email_id']} sent as a new email to {', '.join(recipients)}"
        new = OracleAction(tool="email__send_email", args=args)
        yield _Edit(_where(i, j), what, oracle.replaced(i, j, [new]))


def _new_as_reply(oracle: _Oracle) -> Iterator[_Edit]:
    """A new email to one person sent as a reply to their email on the same subject (of the seed, or the
    one the intervention waits for): the subject becomes "Re: ...", the text and files are the same.
    """
    for i, j, action in oracle.writes:
        recipients = action.args.get("recipients")
        if action.tool != "email__send_email" or action.args.get("cc") or not isinstance(recipients, list):
            continue
        if len(recipients) != 1 or not isinstance(recipients[0], str):
            continue
        when = oracle.interventions[i].when
        arrived = {None, when.event if when else None}
        theirs = [
            (email_id, email)
            for email_id, (email, event) in oracle.emails_with_event.items()
            if event in arrived and str(email.get("sender", "")).lower() == recipients[0].lower()
        ]
        words = _words(f"{action.args.get('subject', '')} {action.args.get('content', '')}")
        scored = [
            (len(words & _words(str(email.get("subject", "")))), email_id) for email_id, email in theirs
        ]
        best = max(scored, default=(0, ""))
        if best[0] == 0:
            continue
        args = {"email_id": best[1], "content": action.args.get("content", "")}
        if action.args.get("attachments"):
            args["attachments"] = action.args["attachments"]
        what = f"the new email to {recipients[0]} sent as a reply to {best[1]}"
        new = OracleAction(tool="email__reply_to_email", args=args)
        yield _Edit(_where(i, j), what, oracle.replaced(i, j, [new]))


def _words(text: str) -> set[str]:
    return {word for word in re.findall(r"[a-z0-9]+", text.lower()) if len(word) > 2 and word != "re"}


_READD: dict[str, tuple[str, str, str, str | None]] = {
    "calendar__edit_calendar_event": (
        "event_id",
        "calendar__delete_calendar_event",
        "calendar__add_calendar_event",
        "updates",
    ),
    "reminder__update_reminder": (
        "reminder_id",
        "reminder__delete_reminder",
        "reminder__add_reminder",
        "updates",
    ),
    "contacts__edit_contact": (
        "contact_id",
        "contacts__delete_contact",
        "contacts__add_new_contact",
        "updates",
    ),
    "notes__update_note": ("note_id", "notes__delete_note", "notes__create_note", None),
}
"""Updates that can be done as a delete and a new item: the id argument, the delete and the add tool, and
the argument holding the changed fields (``None``: the other arguments)."""


def _delete_readd(oracle: _Oracle) -> Iterator[_Edit]:
    """An item of the seed updated by deleting it and adding it again with the changes: the same event,
    reminder, contact or note under a new id. Only an item the add tool can make again whole: not an event
    with attendees (they would be invited again), not one with a field the add cannot set.
    """
    for i, j, action in oracle.writes:
        if action.tool not in _READD:
            continue
        id_key, delete, add, updates_key = _READD[action.tool]
        item_id = action.args.get(id_key)
        add_spec = oracle.catalog.flat.get(add)
        if not isinstance(item_id, str) or add_spec is None or delete not in oracle.catalog.flat:
            continue
        app = action.tool.partition("__")[0]
        item = seed_reading.record(oracle.scenario.seed.get(app, {}), id_key, item_id)
        if item is None:  # an item the story brings later: its fields are not known here
            continue
        updates = (
            action.args.get(updates_key, {})
            if updates_key
            else {k: v for k, v in action.args.items() if k != id_key and v is not None}
        )
        accepted = add_spec.function_schema()["function"]["parameters"]["properties"]
        kept = {
            k: v
            for k, v in {**item, **updates}.items()
            if v not in (None, "", [], {}, False) and not k.endswith("_at")  # a new item's own times
        }
        if kept.get("attendees") or set(kept) - set(accepted) - {id_key}:
            continue  # a new item would invite people again, or lose what the add cannot set (sharing)
        fields = {k: v for k, v in kept.items() if k in accepted}
        actions = [OracleAction(tool=delete, args={id_key: item_id}), OracleAction(tool=add, args=fields)]
        what = f"{action.tool} on {item_id} done as {delete} and {add}"
        yield _Edit(_where(i, j), what, oracle.replaced(i, j, actions))


def _rename_file(oracle: _Oracle) -> Iterator[_Edit]:
    """The attached files copied under other names (``/Documents/attachment-1.pdf``) and the copies
    attached: the same files under names that say nothing. The copies stay: the checks read an attached
    file by the content the Files app keeps under its path.
    """
    if "files__copy_file" not in oracle.catalog.flat:
        return
    for i, j, action in oracle.writes:
        before: list[OracleAction] = []
        args = dict(action.args)
        for key in sorted(_ATTACHMENT_ARGS & set(args)):
            value = args[key]
            paths = value if isinstance(value, list) else [value]
            renamed = []
            for path in paths:
                if not isinstance(path, str) or seed_reading.normal_path(path) not in oracle.files:
                    renamed.append(path)
                    continue
                folder, _, name = seed_reading.normal_path(path).rpartition("/")
                extension = name.rpartition(".")[2] if "." in name else ""
                copy = f"{folder}/attachment-{len(before) + 1}" + (f".{extension}" if extension else "")
                before.append(
                    OracleAction(tool="files__copy_file", args={"source": path, "destination": copy})
                )
                renamed.append(copy)
            args[key] = renamed if isinstance(value, list) else renamed[0]
        if before:
            what = f"{action.tool} with its files attached as copies under other names"
            yield _Edit(_where(i, j), what, oracle.replaced(i, j, [*before, _with_args(action, args)]))


_OPERATORS: dict[str, Operator] = {
    "swap_person": _swap_person,
    "shift_time": _shift_time,
    "drop_action": _drop_action,
    "send_as_draft": _send_as_draft,
    "extra_write": _extra_write,
    "swap_item": _swap_item,
    "change_number": _change_number,
    "swap_file": _swap_file,
    "other_slot": _other_slot,
    "similar_item": _similar_item,
    "early_proposal": _early_proposal,
    "reorder": _reorder,
    "time_phrasing": _time_phrasing,
    "shift_text_time": _shift_text_time,
    "split_message": _split_message,
    "reply_as_new": _reply_as_new,
    "new_as_reply": _new_as_reply,
    "delete_readd": _delete_readd,
    "rename_file": _rename_file,
    "date_phrasing": _date_phrasing,
}
