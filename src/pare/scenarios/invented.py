"""Invented details: a time, day, amount, phone number, link or address the assistant wrote that nothing
in its world gives.

A message that says the doors open at 15:20 when they open at 15:30 passes every check that looks for the
right words elsewhere. So, whatever the scenario's checks, every text the assistant writes into the apps
is read with :func:`pare.scenarios.fact_details.details`, and a detail of a readable kind (``time``,
``date``, ``money``, ``phone``, ``url``, ``email``) that no allowed source states is *invented* and fails
the episode, named in the verdict.

**What is read:** the text fields (:data:`WRITTEN_TEXT_FIELDS`) of the assistant's successful calls to the
apps, also inside a dict argument (an edit's ``updates``): messages, emails, replies, a forward's own words,
titles, descriptions, notes, locations, payment references. Only the assistant's own words: the part of a
text below a forward rule and ``>`` lines are quoted (:func:`pare.scenarios.fact_details.own_words`). What
it says to the user through ``agent_ui`` is not read (the user can ask).

**What is allowed** (a detail is allowed when one of its readings is one of theirs, as for judge facts):

* the scenario's own texts, collected once per scenario (kept on it, in tiers read only as needed): its
  seed data (every string, datetime and amount of every app, but not when an item was written:
  :data:`BOOKKEEPING`), every event's arguments (timed and reactive, with their ``otherwise``
  branches) and facts, the facts of every judge check, and the solutions' texts: everything the oracle and
  the passing variants write (their proposals, reports and every string argument of their actions);
* the episode's own: everything the user and the world wrote (the arguments of every call not the
  assistant's, read as of when it was made, the user's words to the assistant included), the start state,
  and the final state's values other than text fields (the ride's time the assistant booked, the event's
  start it moved, an order's total): a message consistent with what was done is not invented;
* the day the text is sent ("today").

A time is allowed only when a source names it: one inside a range a source gives is not (a delivery window
of 08:00-18:00 does not give "the driver comes at 10am").

**The story's facts.** A detail the world gives somewhere may still be the wrong one ("MOT at 9am", 09:00
being another meeting of the seed). Where the scenario's judge checks have facts, a detail of a kind
they give must also be one the facts, the criteria or the solutions' texts give, or one the assistant
did (:func:`done_values`); otherwise it is named as one "the story's facts do not give"
(:func:`story_details`). Counts, parts of the day, codes and streets, which the world is not read for,
are read here.

A datetime written as a value (``2025-06-02T10:00:00``) gives its day and its clock time; a number under
a money-like key (``price``, ``total``, ``amount``...) gives that amount in any currency (``_cents``:
divided by 100). A scenario whose story asks the assistant to compute new values opts out per kind with
``invented_details: {allow: [money], reason: ...}``.
"""

from __future__ import annotations

import re
from collections.abc import Callable, Iterable, Iterator, Mapping, Sequence
from dataclasses import dataclass
from datetime import datetime
from decimal import Decimal, InvalidOperation
from typing import Any, Literal

from pare.scenarios.claims import Claim, claims, unbacked
from pare.scenarios.fact_details import WORLD_KINDS, AllowedDetails, Detail, Kind, details, excerpt, own_words
from pare.scenarios.item_text import TEXT_FIELDS as ITEM_TEXT_FIELDS
from pare.scenarios.leaves import leaves
from pare.scenarios.model import Scenario
from pare.scenarios.read_moment import fires_at
from pare.scenarios.times import TimeFormatError, parse_time
from pare.sim.log import LogEntry

WRITTEN_TEXT_FIELDS: frozenset[str] = frozenset(ITEM_TEXT_FIELDS) | {
    "body", "note", "message", "text", "reason", "reference", "group_title", "headline"
}  # fmt: skip
"""Argument and item fields that hold free text (an item's text fields and the free-text arguments of
calls): what the assistant writes there is read; what the final state holds there is not a value the
episode set."""

_TARGET_FIELDS = ("recipients", "recipient", "to", "user_id", "user_ids", "participant_ids",
                  "conversation_id", "email_id", "event_id", "reminder_id", "note_id", "path",
                  "item_id")  # fmt: skip
"""The argument that says where a text went, for the verdict (the first one a call has)."""
_MONEY_KEYS = ("price", "amount", "total", "cost", "fare", "fee", "balance", "cents", "deposit", "rent",
               "refund", "paid", "charge", "excess", "premium")  # fmt: skip
_CURRENCIES = ("GBP", "USD", "EUR")
BOOKKEEPING: frozenset[str] = frozenset(
    {"timestamp", "created_at", "updated_at", "modified", "placed_at", "booked_at", "sent_at", "received_at",
     "last_updated", "read_at", "deleted_at", "cancelled_at", "completed_at"}
)  # fmt: skip
"""Fields that say when an item was written, not what it is about: no detail a text states comes from
them (an email received at 10:00 does not make "the driver comes at 10am" true)."""
_CONTROL_APPS = frozenset({"system", "agent_ui"})
_RELATIVE = re.compile(r"^\s*(?:day\b|[+-]\s*\d)")
"""A time written relative to the scenario's start (``day+1 09:00``, ``day 14:00``, ``+2h``)."""


@dataclass(frozen=True, slots=True)
class InventedDetail:
    """One detail the assistant wrote that nothing in the scenario or the episode gives."""

    order: int
    """The log index of the call that wrote it."""
    tool: str
    """The call, as ``app__tool``."""
    target: str
    """Where the text went (a recipient, an item), as the call names it; empty when not known."""
    field: str
    """The argument holding the text (``updates.description`` inside an edit)."""
    kind: Kind | Literal["act"]
    """The detail's kind, or ``act``: an act the text claims as done that no call did
    (:mod:`pare.scenarios.claims`)."""
    shown: str
    """The detail as written ("10:00", "£1,642", "I've cancelled")."""
    excerpt: str
    """The words around it."""
    against_facts: bool = False
    """Whether it is the story's facts that do not give it (the world gives it somewhere, in a kind the
    facts give, but neither they nor a solution state it); else nothing in the scenario gives it."""

    @property
    def against(self) -> str:
        """What does not give it, as the verdict says: "the story's facts", "nothing in the scenario" or,
        for a claimed act, "no call of the episode".
        """
        if self.kind == "act":
            return "no call of the episode"
        return "the story's facts" if self.against_facts else "nothing in the scenario"

    def describe(self) -> str:
        """One line: ``#14 messaging__send_message to user-jonas states 10:00, which nothing in the
        scenario gives ("... comes at 10:00 ...")``.
        """
        where = f" to {self.target}" if self.target else ""
        if self.kind == "act":
            return (
                f'#{self.order} {self.tool}{where} claims "{self.shown}" in {self.field}, which no call of '
                f'the episode did ("{self.excerpt}")'
            )
        return (
            f"#{self.order} {self.tool}{where} states {self.shown} in {self.field}, which {self.against} "
            f'{"do not give" if self.against_facts else "gives"} ("{self.excerpt}")'
        )

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready form, with the sentence."""
        return {
            "order": self.order,
            "tool": self.tool,
            "target": self.target,
            "field": self.field,
            "kind": self.kind,
            "shown": self.shown,
            "excerpt": self.excerpt,
            "against": self.against,
            "text": self.describe(),
        }


def checked_kinds(scenario: Scenario) -> frozenset[Kind]:
    """The kinds of detail checked in ``scenario``: all but those it allows (``invented_details``)."""
    allowance = scenario.invented_details
    return frozenset(WORLD_KINDS) - frozenset(allowance.allow if allowance is not None else ())


class ScenarioAllowed:
    """The details the scenario's own texts give (see the module's docstring), in tiers read only when a
    detail is not in the ones before: what the solutions write and the facts (where most of what an
    assistant writes is found), then the events, then the seed.
    """

    def __init__(self, scenario: Scenario) -> None:
        self.scenario = scenario
        self.kinds = checked_kinds(scenario)
        self._tiers: list[AllowedDetails] = []
        self._builders: list[Callable[[AllowedDetails], None]] = [self._solutions, self._events, self._seed]

    def allows(self, detail: Detail, sent: datetime) -> bool:
        """Whether some text of the scenario gives ``detail`` (of a text sent at ``sent``)."""
        for number, build in enumerate(self._builders):
            if number == len(self._tiers):
                tier = AllowedDetails.of_texts((), self.scenario.start, self.kinds)
                build(tier)
                self._tiers.append(tier)
            if self._tiers[number].allows(detail, sent):
                return True
        return False

    def _solutions(self, allowed: AllowedDetails) -> None:
        scenario = self.scenario
        for goal in scenario.goals:
            for check in goal.checks:
                if check.judge is not None:
                    allowed.add(check.judge.facts)
        for event in scenario.events:
            if event.judge is not None:
                allowed.add(event.judge.facts)
        for name in scenario.right_solutions():
            for intervention in scenario.solution(name).interventions:
                allowed.add((intervention.proposal, intervention.report))
                for action in intervention.actions:
                    _allow_values(allowed, action.args, scenario.start)

    def _events(self, allowed: AllowedDetails) -> None:
        for event in self.scenario.events:
            _allow_values(allowed, event.args, self.scenario.start)
            if event.otherwise is not None:
                _allow_values(allowed, event.otherwise.args, self.scenario.start)

    def _seed(self, allowed: AllowedDetails) -> None:
        _allow_seed(allowed, self.scenario.seed, self.scenario.start)


_WRITTEN_AT = ("timestamp", "sent_at", "received_at", "created_at")
"""The fields that say when a seed item was written: its days ("Saturday", "yesterday") are read as of
then."""


def _allow_seed(allowed: AllowedDetails, value: Any, anchor: datetime) -> None:
    """Allow what the seed ``value`` holds (as :func:`_allow_values` does), each item's texts read as of
    when it was written where it says so (a message of last Tuesday that says "Saturday" means the
    Saturday after it, not the one after the scenario's start).
    """
    if isinstance(value, Mapping):
        written = next(
            (moment for key in _WRITTEN_AT if isinstance(value.get(key), str)
             if (moment := _datetime(value[key], anchor)) is not None),
            None,
        )  # fmt: skip
        if written is not None and written != anchor:
            _allow_values(allowed, value, anchor)  # as of the start too: the scenario's own reading
            _allow_values(allowed, value, written)
            return
        for key, item in value.items():
            if isinstance(item, Mapping | list):
                _allow_seed(allowed, item, anchor)
            else:
                _allow_values(allowed, {key: item}, anchor)
    elif isinstance(value, list):
        for item in value:
            _allow_seed(allowed, item, anchor)
    else:
        _allow_values(allowed, value, anchor)


def scenario_allowed(scenario: Scenario) -> ScenarioAllowed:
    """The details the scenario's own texts give, kept on the scenario (each tier read once)."""
    known: ScenarioAllowed | None = scenario.known(ScenarioAllowed)
    return known if known is not None else scenario.keep(ScenarioAllowed, ScenarioAllowed(scenario))


def invented_details(
    scenario: Scenario, log: Sequence[LogEntry], start: Mapping[str, Any], final: Mapping[str, Any]
) -> list[InventedDetail]:
    """Every detail the assistant wrote into the apps in the episode of ``scenario`` (its ``log``, from
    the ``start`` to the ``final`` state) that no allowed source states, in the order written. A
    reminder's text is read as of when it is written and as of when it fires: it states a wrong detail only
    if it does both ways (:mod:`pare.scenarios.read_moment`).
    """
    written = [(entry, field, text) for entry in log for field, text in assistant_texts(entry)]
    if not written:
        return []
    kinds = checked_kinds(scenario)
    if not kinds:
        return _false_claims(written, log, (start, final))
    reading = _Reading(scenario, kinds, log, start, final)
    found: list[InventedDetail] = []
    for entry, field, text in written:
        words = own_words(text)
        stated = reading.unsupported(words, entry.time)
        fires = fires_at(entry)
        if stated and fires is not None and not reading.unsupported(words, fires):
            stated = []
        found += [_invented(entry, field, detail, words, against_facts=facts) for detail, facts in stated]
    return sorted([*found, *_false_claims(written, log, (start, final))], key=lambda one: one.order)


def _false_claims(
    written: Sequence[tuple[LogEntry, str, str]],
    log: Sequence[LogEntry],
    world: Sequence[Mapping[str, Any]],
) -> list[InventedDetail]:
    """The acts the assistant's texts claim as done that no call of the episode did (to what the claim
    names of the ``world``: the start and final states).
    """
    found: list[InventedDetail] = []
    for entry, field, text in written:
        words = own_words(text)
        found += [
            _invented(entry, field, claim, words) for claim in unbacked(claims(words), log, entry, world)
        ]
    return found


class _Reading:
    """What an episode's texts are read against: the scenario's texts, the story's facts, what the
    assistant did and the episode's own texts (the last two read only when needed).
    """

    def __init__(
        self,
        scenario: Scenario,
        kinds: frozenset[Kind],
        log: Sequence[LogEntry],
        start: Mapping[str, Any],
        final: Mapping[str, Any],
    ) -> None:
        self.scenario, self.kinds, self.log, self.start, self.final = scenario, kinds, log, start, final
        self.allowed = scenario_allowed(scenario)
        self.story = story_details(scenario)
        self._episode: AllowedDetails | None = None
        self._done: AllowedDetails | None = None

    def unsupported(self, words: str, at: datetime) -> list[tuple[Detail, bool]]:
        """The details of ``words`` read as of ``at`` that no source gives, each with whether it is the
        story's facts that do not give it (the world does).
        """
        found: list[tuple[Detail, bool]] = []
        for detail in sorted(details(words, at), key=lambda one: one.start):
            if self.allowed.allows(detail, at):
                # the world gives it, but where the story's facts give details of its kind, one that neither
                # they nor the solutions give, nor what the assistant did, is a wrong detail ("MOT at 9am"
                # in a reminder, 09:00 being the seed's planning meeting)
                story = self.story
                if story is not None and detail.kind in story.kinds and not story.allows(detail, at):
                    if self._done is None:
                        self._done = done_values(self.log, self.scenario.start)
                    if not self._done.allows_read(detail, at):
                        found.append((detail, True))
                continue
            if self._episode is None:  # most details are the scenario's: read the episode only if not
                self._episode = _episode_allowed(
                    self.scenario.start, self.kinds, self.log, self.start, self.final
                )
            if not self._episode.allows(detail, at):
                found.append((detail, False))
        return found


@dataclass(frozen=True, slots=True)
class _StoryFacts:
    """The story's facts of a scenario, kept on it (:func:`story_details`)."""

    allowed: AllowedDetails | None


def story_details(scenario: Scenario) -> AllowedDetails | None:
    """The details the story's facts allow (the facts of every goal's judge checks, widened by the
    criteria and by every text the scenario's solutions write), or ``None`` when it has no facts; made once
    per scenario.
    """
    return scenario.derived(_StoryFacts, lambda: _StoryFacts(_story_details(scenario))).allowed


def _story_details(scenario: Scenario) -> AllowedDetails | None:
    facts = [fact for goal in scenario.goals for check in goal.checks if check.judge is not None
             for fact in check.judge.facts]  # fmt: skip
    if not facts:
        return None

    def more() -> list[str]:
        texts = [check.judge.criterion for goal in scenario.goals for check in goal.checks if check.judge]
        for name in scenario.right_solutions():
            for intervention in scenario.solution(name).interventions:
                texts += [intervention.proposal, intervention.report]
                for action in intervention.actions:
                    texts += [leaf for _, leaf in leaves(action.args, "") if isinstance(leaf, str)]
        return texts

    return AllowedDetails.of(facts, scenario.start, more)


def _invented(
    entry: LogEntry,
    field: str,
    detail: Detail | Claim,
    words: str,
    *,
    against_facts: bool = False,
) -> InventedDetail:
    """What the verdict says of ``detail``: a detail no source gives, or an act no call did (kind ``act``)."""
    target = next((entry.args[name] for name in _TARGET_FIELDS if entry.args.get(name)), "")
    shown_target = ", ".join(map(str, target)) if isinstance(target, list) else str(target)
    return InventedDetail(
        entry.index,
        f"{entry.app}__{entry.tool}",
        shown_target,
        field,
        "act" if isinstance(detail, Claim) else detail.kind,
        detail.shown,
        excerpt(words, detail.start, detail.end),
        against_facts,
    )


def assistant_texts(entry: LogEntry) -> Iterator[tuple[str, str]]:
    """(field, text) for each free text a log entry has the assistant write into the apps: the
    :data:`WRITTEN_TEXT_FIELDS` of a successful write's arguments, also one level inside a dict argument.
    """
    if entry.actor != "assistant" or not entry.ok or entry.kind != "write" or entry.app in _CONTROL_APPS:
        return
    for name, value in entry.args.items():
        if isinstance(value, str) and name in WRITTEN_TEXT_FIELDS and value.strip():
            yield name, value
        elif isinstance(value, Mapping):
            for inner, text in value.items():
                if isinstance(text, str) and inner in WRITTEN_TEXT_FIELDS and text.strip():
                    yield f"{name}.{inner}", text


def _episode_allowed(
    begin: datetime,
    kinds: frozenset[Kind],
    log: Sequence[LogEntry],
    start: Mapping[str, Any],
    final: Mapping[str, Any],
) -> AllowedDetails:
    """The details the episode gives: what the user and the world wrote, the start state, and the final
    state's values that are not free text.
    """
    allowed = AllowedDetails.of_texts((), begin, kinds)
    for entry in log:
        if entry.actor != "assistant":
            _allow_values(allowed, entry.args, entry.time)
    _allow_values(allowed, start, begin)
    _allow_values(allowed, final, begin, texts=False)
    return allowed


def done_values(log: Sequence[LogEntry], begin: datetime) -> AllowedDetails:
    """The details of what the assistant did: the values of its successful writes and of what they
    returned (the ride's time booked, the event's new start, an order's total), not their free text, of
    the kinds read everywhere. A text that states one of them tells what was done, which is no invented
    or contradicted detail: whether what was done is right is the business of the checks of the state.
    """
    allowed = AllowedDetails.of_texts((), begin, frozenset(WORLD_KINDS))
    for entry in log:
        if entry.actor == "assistant" and entry.ok and entry.kind == "write":
            _allow_values(allowed, entry.args, entry.time, texts=False)
            _allow_values(allowed, _without_echo(entry.result, entry.args), entry.time, texts=False)
    return allowed


def _without_echo(result: Any, args: Mapping[str, Any]) -> Any:
    """``result`` with the free text the call wrote taken out where it echoes it ("Added event ... 'Cab
    08:45'"): a text the assistant wrote tells nothing of what was done.
    """
    written = sorted(
        {
            leaf
            for key, leaf in leaves(args, "")
            if key in WRITTEN_TEXT_FIELDS and isinstance(leaf, str) and leaf
        },
        key=len,
        reverse=True,
    )
    if not written:
        return result

    def strip(value: Any) -> Any:
        if isinstance(value, str):
            for text in written:
                value = value.replace(text, " ")
            return value
        if isinstance(value, Mapping):
            return {key: strip(item) for key, item in value.items()}
        if isinstance(value, list):
            return [strip(item) for item in value]
        return value

    return strip(result)


def _allow_values(allowed: AllowedDetails, value: Any, anchor: datetime, *, texts: bool = True) -> None:
    """Allow what ``value`` (arguments, seed data, a state) holds: its texts (with ``texts``), datetimes
    written as values, and amounts under money-like keys.
    """
    strings: list[str] = []
    for key, leaf in leaves(value, ""):
        if key in BOOKKEEPING:
            continue
        if isinstance(leaf, str):
            moment = _datetime(leaf, anchor)
            if moment is not None:
                allowed.add_readings("time", {moment.time().replace(tzinfo=None)})
                allowed.add_readings("date", {moment.date(), ("weekday", moment.weekday())})
            elif texts or key not in WRITTEN_TEXT_FIELDS:
                strings.append(leaf)
        elif isinstance(leaf, int | float) and not isinstance(leaf, bool) and _is_money(key):
            amount = _amount(leaf, cents=key.endswith("cents"))
            if amount is not None:
                allowed.add_readings("money", {(currency, amount) for currency in _CURRENCIES})
    allowed.add(strings, anchor)


def _datetime(text: str, anchor: datetime) -> datetime | None:
    """The moment ``text`` is when it is a datetime written as a value: ISO, or relative as a scenario
    writes it (``day+1 09:00``, ``+2h``).
    """
    iso = len(text) >= 16 and text[:4].isdigit() and text[4] == "-" and text[10] in "T "
    if not iso and _RELATIVE.match(text) is None:
        return None
    try:
        return parse_time(text, anchor)
    except TimeFormatError:
        return None


def _is_money(key: str) -> bool:
    lowered = key.lower()
    return any(word in lowered for word in _MONEY_KEYS)


def _amount(number: float, *, cents: bool) -> Decimal | None:
    try:
        value = Decimal(str(number))
    except InvalidOperation:  # pragma: no cover - a float always converts
        return None
    return (value / 100 if cents else value).normalize()


def describe_all(found: Iterable[InventedDetail]) -> list[str]:
    """The sentences of several invented details, for a verdict's reasons."""
    return [f"invented: {detail.describe()}" for detail in found]
