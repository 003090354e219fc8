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
from typing import Any, Literal

from pare.apps.files import normalize_path
from pare.errors import ToolError
from pare.scenarios.model import (
    MUTANT_OPERATORS,
    REWRITE_OPERATORS,
    Intervention,
    OracleAction,
    Scenario,
    Solution,
)
from pare.scenarios.validation import ToolCatalog

PER_OPERATOR = 3
"""At most this many mutants (or rewrites) of one operator per scenario: the first places it applies to.
Enough to show what an operator finds; the gate stays fast on the whole library."""

_DAY = re.compile(r"^day(?:([+-])(\d+))?\s+(\d{1,2}):(\d{2})(?::(\d{2}))?$")
_EMAIL = re.compile(r"[\w.+-]+@[\w-]+(?:\.[\w-]+)+")
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
            found.append(Mutant(name, operator, expect, edit.what, solution))
            if len(seen) == PER_OPERATOR:
                break
    return found


class _Oracle:
    """A scenario's oracle and seed, read for what the operators need."""

    def __init__(self, scenario: Scenario) -> None:
        self.scenario = scenario
        self.interventions = tuple(scenario.oracle.interventions)
        catalog = ToolCatalog(scenario.all_apps)
        self.writes = [
            (i, j, action)
            for i, intervention in enumerate(self.interventions)
            for j, action in enumerate(intervention.actions)
            if (spec := catalog.flat.get(action.tool)) is not None and spec.kind == "write"
        ]
        """The assistant's writes, with their intervention's and their own index."""
        self.people = _people(scenario.seed)
        self.files = _files(scenario.seed)
        passing = [None, *(variant.id for variant in scenario.variants if variant.expect == "pass")]
        self.used = frozenset(
            text
            for name in passing
            for intervention in scenario.solution(name).interventions
            for action in intervention.actions
            for text in _strings(action.args)
        )
        """Every string the actions of the oracle and of the passing variants give: the items (and files)
        a right solution is about; the others are distractors."""

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
    known = [
        *(oracle.scenario.seed.get("email", {}).get("emails", []) or []),
        *(event.args for event in oracle.scenario.events if event.tool == "email__receive_email"),
    ]
    emails = {str(email.get("email_id")): email for email in known if isinstance(email, Mapping)}
    for i, j, action in oracle.writes:
        args = dict(action.args)
        if action.tool == "email__reply_to_email":
            replied = emails.get(str(args.pop("email_id", "")))
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
    seed = oracle.scenario.seed.get(action.tool.partition("__")[0], {})
    places = _places(seed)
    for key in sorted(action.args):
        value = action.args[key]
        if not key.endswith("_id") or key in _PEOPLE_ARGS or not isinstance(value, str):
            continue
        ids = _ids(seed, key)
        if value not in ids:  # an item the story brings later: where its kind is kept is not in the seed
            continue
        # a distractor: no right solution's item; one found where the item is, if any (a saved flat for a
        # saved flat: removing a flat that is not saved changes nothing)
        others = sorted(ids - oracle.used)
        alike = [other for other in others if places[other] >= places[value]]
        if others:
            yield key, oracle.rng(f"{operator}:{_where(i, j, key)}").choice(alike or others)


def _ids(data: Any, key: str) -> set[str]:
    """Every string under ``key`` anywhere in ``data``."""
    found: set[str] = set()
    if isinstance(data, Mapping):
        for name, item in data.items():
            if name == key and isinstance(item, str):
                found.add(item)
            else:
                found |= _ids(item, key)
    elif isinstance(data, list):
        for item in data:
            found |= _ids(item, key)
    return found


def _places(data: Any, path: str = "") -> dict[str, set[str]]:
    """Each string in ``data`` with the places it is found at (paths, a list's items all at ``*``)."""
    found: dict[str, set[str]] = {}
    children: list[tuple[str, Any]] = []
    if isinstance(data, Mapping):
        children = [(f"{path}.{name}", item) for name, item in data.items()]
    elif isinstance(data, list):
        children = [(f"{path}[*]", item) for item in data]
    elif isinstance(data, str):
        found[data] = {path}
    for place, item in children:
        for text, where in _places(item, place).items():
            found.setdefault(text, set()).update(where)
    return found


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
        if not isinstance(path, str) or _is_reference(path) or _normal(path) not in oracle.files:
            continue
        attached = {oracle.files[_normal(p)] for p in values if _normal(str(p)) in oracle.files}
        # another content: a copy of the same file under another path is the same file
        others = sorted(other for other, content in oracle.files.items() if content not in attached)
        same_kind = [p for p in others if p.rpartition(".")[2] == path.rpartition(".")[2]]
        if not others:
            continue
        where = _where(i, j, f"{key}[{position}]")
        other = oracle.rng(f"swap_file:{where}").choice(same_kind or others)
        what = f"{action.tool} {key}: {path} -> {other}"
        yield _Edit(where, what, oracle.replaced(i, j, [_swapped(action, key, position, other)]))


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
    shared = _strings(first.args) & _strings(second.args)
    return not {value for value in shared if len(value) >= 4 and not value.isdigit()}


def _strings(value: Any) -> set[str]:
    if isinstance(value, str):
        return {value}
    if isinstance(value, Mapping):
        return {text for item in value.values() for text in _strings(item)}
    if isinstance(value, list):
        return {text for item in value for text in _strings(item)}
    return set()


def _time_phrasing(oracle: _Oracle) -> Iterator[_Edit]:
    """The clock times in a sent or written text in the 12-hour form: 09:30 as 9:30am, 18:00 as 6pm."""
    for i, j, action in oracle.writes:
        for key in sorted(action.args):
            value = action.args[key]
            if key not in (*_SPLIT_FIELDS, "description", "title", "subject", "notes") or not isinstance(
                value, str
            ):
                continue
            rephrased = _CLOCK.sub(_twelve_hour, value)
            if rephrased != value:
                args = {**action.args, key: rephrased}
                what = f"{action.tool} {key} with its times as " + ", ".join(
                    _twelve_hour(m) for m in _CLOCK.finditer(value)
                )
                yield _Edit(_where(i, j, key), what, oracle.replaced(i, j, [_with_args(action, args)]))


def _twelve_hour(match: re.Match[str]) -> str:
    hour, minute = int(match.group(1)), int(match.group(2))
    suffix = "am" if hour < 12 else "pm"
    clock = hour % 12 or 12
    return f"{clock}{suffix}" if minute == 0 else f"{clock}:{minute:02d}{suffix}"


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


_OPERATORS: dict[str, Operator] = {
    "swap_person": _swap_person,
    "shift_time": _shift_time,
    "drop_action": _drop_action,
    "send_as_draft": _send_as_draft,
    "extra_write": _extra_write,
    "swap_item": _swap_item,
    "change_number": _change_number,
    "swap_file": _swap_file,
    "reorder": _reorder,
    "time_phrasing": _time_phrasing,
    "split_message": _split_message,
}


# -- the seed, read -----------------------------------------------------------------------------------
def _people(seed: Mapping[str, Mapping[str, Any]]) -> list[frozenset[str]]:
    """The people of the seed, in three forms each a pool: email addresses, messaging user ids, and full
    names (of contacts and messaging users). The user is in none of them.
    """
    email = seed.get("email", {})
    own = {str(email.get("user_email", "")).lower()}
    addresses = {found for found in _EMAIL.findall(repr(seed)) if found.lower() not in own}
    messaging = seed.get("messaging", {})
    users = messaging.get("users", {}) if isinstance(messaging.get("users"), Mapping) else {}
    me = messaging.get("current_user_id")
    ids = {str(user) for user in users if user != me}
    names = {str(name) for user, name in users.items() if user != me}
    for contact in seed.get("contacts", {}).get("contacts", []) or []:
        if (
            isinstance(contact, Mapping)
            and contact.get("first_name")
            and contact.get("contact_id") != "contact-me"
        ):
            names.add(f"{contact['first_name']} {contact.get('last_name') or ''}".strip())
    return [frozenset(pool) for pool in (addresses, ids, names) if pool]


def _files(seed: Mapping[str, Mapping[str, Any]]) -> dict[str, str]:
    """The seed's files: each normalised path with its content."""
    files = seed.get("files", {}).get("files", {})
    if not isinstance(files, Mapping):
        return {}
    return {
        _normal(path): str(entry.get("content", "") if isinstance(entry, Mapping) else entry)
        for path, entry in files.items()
    }


def _normal(path: str) -> str:
    try:
        return normalize_path(path)
    except ToolError:  # a path the phone would refuse is simply no seed file
        return path
