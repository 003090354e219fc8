"""The scenario file format, as pydantic models (the JSON Schema is generated from these).

A scenario is data only: the story, the apps and their seed data, the events the world schedules, the
oracle (what a perfect assistant proposes and does, and what the user does), and the user's goals with
declarative checks. :mod:`pare.scenarios.loader` reads a file into a :class:`Scenario` and validates it
against the apps; nothing in a scenario file runs code.
"""

from __future__ import annotations

import functools
import hashlib
import json
import re
from collections.abc import Callable, Hashable, Iterator, Mapping
from dataclasses import dataclass
from datetime import UTC, datetime
from typing import TYPE_CHECKING, Annotated, Any, Literal, Self, TypeVar

from pydantic import (
    BaseModel,
    ConfigDict,
    Field,
    GetJsonSchemaHandler,
    RootModel,
    SerializerFunctionWrapHandler,
    TypeAdapter,
    WithJsonSchema,
    field_validator,
    model_serializer,
    model_validator,
)
from pydantic.json_schema import JsonSchemaValue
from pydantic_core import CoreSchema

from pare.apps.registry import phone_apps
from pare.errors import did_you_mean
from pare.scenarios.matchers import MatcherError, compile_matcher
from pare.scenarios.operator_docs import matcher_description
from pare.scenarios.times import TimeFormatError, parse_duration, parse_time
from pare.scenarios.told import CHANNELS, Channel
from pare.sim.log import AssistantMode, ToolKind

FORMAT_VERSION = 1
"""Version of the scenario file format; bumped when a file valid before would be read differently."""

Tag = Literal["context_observation", "goal_inference", "intervention_timing", "multi_app_orchestration"]
TAGS: tuple[Tag, ...] = (
    "context_observation",
    "goal_inference",
    "intervention_timing",
    "multi_app_orchestration",
)
Difficulty = Literal["easy", "medium", "hard"]
ActorPattern = Literal["user", "assistant", "env", "any"]

_ID = re.compile(r"^[a-z][a-z0-9_]*$")
MAX_SCENARIO_ID_LENGTH = 100
"""The longest scenario id: it names files (``<id>.yaml``, a run's ``trajectories/<id>/``), and file systems
allow 255 bytes a name; the library's longest is under 60."""
_REF = re.compile(r"^\$\{([A-Za-z0-9_-]+)(?:\.([A-Za-z0-9_.\[\]-]+))?\}$")


class _MatcherSchema:
    """A matcher's JSON Schema: its description, naming the operators registered when it is made."""

    def __get_pydantic_json_schema__(
        self, core: CoreSchema, handler: GetJsonSchemaHandler
    ) -> JsonSchemaValue:
        return {"description": matcher_description()}


Matcher = Annotated[Any, _MatcherSchema()]
TimeText = Annotated[
    str,
    WithJsonSchema(
        {
            "type": "string",
            "description": "An ISO time, an offset from the start (+15m, -2h, +1d2h) or a day and clock time "
            "(day+1 09:00).",
        }
    ),
]
DurationText = Annotated[
    str | int,
    WithJsonSchema(
        {
            "anyOf": [{"type": "string"}, {"type": "integer", "minimum": 0}],
            "description": "A duration: 10m, 1h30m, 2d, 45s, or a number of seconds.",
        }
    ),
]


def reference(value: Any) -> tuple[str, str] | None:
    """For a ``${step.field}`` string (a value produced while the scenario runs): the step and field;
    for ``${step}`` (the whole result, e.g. a downloaded file's path), the step and ``""``.
    """
    if isinstance(value, str):
        found = _REF.match(value.strip())
        if found:
            return found.group(1), found.group(2) or ""
    return None


_DERIVED = "_derived"
"""Key in a scenario part's ``__dict__`` (not a field) of what was computed from it (see ``_Strict.keep``)."""
_T = TypeVar("_T")


class _Strict(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True)

    # -- what is computed from a scenario part, kept on it ----------------------------------------------
    # Compiled checks, an environment blueprint, an envelope: every episode of a scenario needs the same
    # ones, and the parts are immutable, so each is computed once and kept on the object it came from
    # (in its ``__dict__`` beside the fields, where pydantic's equality and dumps do not look). A copy
    # starts without any: one made with updated fields would otherwise reuse what the original computed.

    def known(self, key: Hashable) -> Any:
        """What was kept on this object under ``key`` (see :meth:`keep`), or ``None``."""
        store = self.__dict__.get(_DERIVED)
        return None if store is None else store.get(key)

    def keep(self, key: Hashable, value: _T) -> _T:
        """Keep ``value``, computed from this object alone, under ``key``; return it."""
        self.__dict__.setdefault(_DERIVED, {})[key] = value
        return value

    def derived(self, key: Hashable, make: Callable[[], _T]) -> _T:
        """``make()``, computed from this object alone, once: later calls with ``key`` return it."""
        known: _T | None = self.known(key)
        return known if known is not None else self.keep(key, make())

    def __copy__(self) -> Self:
        copied = super().__copy__()
        copied.__dict__.pop(_DERIVED, None)
        return copied

    def __deepcopy__(self, memo: dict[int, Any] | None = None) -> Self:
        copied = super().__deepcopy__(memo)
        copied.__dict__.pop(_DERIVED, None)
        return copied

    def __getstate__(self) -> dict[Any, Any]:
        state = super().__getstate__()
        fields = state.get("__dict__")
        if isinstance(fields, dict) and _DERIVED in fields:  # compiled artefacts stay in their process
            state = {**state, "__dict__": {k: v for k, v in fields.items() if k != _DERIVED}}
        return state


def _valid_matcher(raw: Any, label: str = "") -> Any:
    """``raw`` if it compiles as a matcher; else a ``ValueError`` (a pydantic error) prefixed by ``label``."""
    try:
        compile_matcher(raw)
    except MatcherError as error:
        raise ValueError(f"{label}{error}") from None
    return raw


WHERE_KEY = "_key"
"""In a state check's ``where``: the item's key in a keyed collection (a file's path in ``files.files``)."""
WHERE_TEXT = "_text"
"""In a state check's ``where``: all of an item's text fields read together (its title, description, ...;
see :mod:`pare.scenarios.item_text`), for words that may be written in any of them."""
WHERE_ANY = "any_of"
"""In a state check's ``where``: a list of field conditions, of which an item must meet one (a name in
the first or the last name field)."""


def _check_where(where: dict[str, Any]) -> dict[str, Any]:
    for name, raw in where.items():
        if name != WHERE_ANY:
            _valid_matcher(raw, f"field '{name}': ")
            continue
        if not isinstance(raw, list) or not raw or not all(isinstance(item, dict) and item for item in raw):
            raise ValueError(
                "'any_of' in a where lists alternatives, each a mapping of fields to matchers: "
                "any_of: [{first_name: {contains: helen}}, {last_name: {contains: helen}}]"
            )
        for alternative in raw:
            _check_where(alternative)
    return where


def _check_matchers(args: dict[str, Any]) -> dict[str, Any]:
    for name, raw in args.items():
        _valid_matcher(raw, f"argument '{name}': ")
    return args


class ActionPattern(_Strict):
    """Which action-log entries are meant: by actor, tool or app, kind, mode and arguments."""

    actor: ActorPattern = Field(
        default="assistant", description="Who made the call; 'any' for anyone. Default: the assistant."
    )
    tool: str | list[str] | None = Field(
        default=None,
        description="The tool as app__tool (email__send_email); for user screen actions the app and the "
        "action's name (email__open_email). A list means any of those tools.",
    )
    app: str | None = Field(default=None, description="Any tool of this app (when no tool is given).")
    kind: ToolKind | None = Field(default=None, description="Only calls of this kind (read, write, ...).")
    mode: AssistantMode | None = Field(default=None, description="Only assistant calls in this mode.")
    args: dict[str, Matcher] = Field(default_factory=dict, description="Argument name to matcher.")
    result: Matcher | None = Field(default=None, description="A matcher on the call's result.")
    screen: Matcher | None = Field(
        default=None,
        description="For user actions: a matcher on where the user was, the app and screen with what it "
        "shows (email > Detail(email_id='e-7')): a reply on an email's screen names no email_id.",
    )
    ok: bool | None = Field(
        default=True, description="Only successful calls (true, the default), failed ones, or any (null)."
    )
    after_event: str | None = Field(default=None, description="Only calls made after this event fired.")
    before_event: str | None = Field(
        default=None, description="Only calls made before this event fired (or if it never did)."
    )
    to: str | list[str] | None = Field(
        default=None,
        description="Only calls that told this person something (an email address or a messaging user "
        "id; a list: any of them): an email to, CC, a reply or a forward reaching them, a message in a "
        "one-to-one or group conversation that includes them. Arguments 'content' and 'attachments' "
        "then read what they got (a forward's text is the forwarded email).",
    )
    via: list[Channel] | None = Field(
        default=None,
        description="With 'to': only through these channels ("
        + "; ".join(f"{name}: {text}" for name, text in CHANNELS.items())
        + "). Default: any.",
    )

    @field_validator("tool")
    @classmethod
    def _tools_named(cls, value: str | list[str] | None) -> str | list[str] | None:
        if isinstance(value, list) and (not value or len(set(value)) != len(value)):
            raise ValueError("a list of tools names each tool once, and at least one")
        return value

    @field_validator("to")
    @classmethod
    def _people_named(cls, value: str | list[str] | None) -> str | list[str] | None:
        named = [value] if isinstance(value, str) else value
        if named is not None and (not named or not all(person.strip() for person in named)):
            raise ValueError(
                "'to' names a person by an email address or a messaging user id (or a list of them)"
            )
        return value

    @model_validator(mode="after")
    def _via_with_to(self) -> ActionPattern:
        if self.via is not None and self.to is None:
            raise ValueError("'via' narrows 'to': give the person it tells about")
        if self.via is not None and not self.via:
            raise ValueError("'via' lists at least one channel (or leave it out for any)")
        return self

    @model_serializer(mode="wrap")
    def _without_unused_recipients(self, handler: SerializerFunctionWrapHandler) -> dict[str, Any]:
        # 'to' and 'via' came after the scenarios: left out when unused, a pattern dumps (and so a
        # scenario hashes, see Scenario.content_hash) as it did before them, and run folders stay valid
        data: dict[str, Any] = handler(self)
        for name in ("to", "via"):
            if data.get(name) is None:
                data.pop(name, None)
        return data

    @property
    def people(self) -> frozenset[str] | None:
        """Who a matching call must have told (lowercase handles), or ``None`` for no one in particular."""
        if self.to is None:
            return None
        return frozenset(
            person.strip().lower() for person in ([self.to] if isinstance(self.to, str) else self.to)
        )

    @property
    def tools(self) -> tuple[str, ...] | None:
        """The tools meant (any of them), or ``None`` for any tool."""
        if self.tool is None:
            return None
        return (self.tool,) if isinstance(self.tool, str) else tuple(self.tool)

    @field_validator("args")
    @classmethod
    def _check_args(cls, value: dict[str, Any]) -> dict[str, Any]:
        return _check_matchers(value)

    @field_validator("result")
    @classmethod
    def _check_result(cls, value: Any) -> Any:
        return value if value is None else _valid_matcher(value, "result: ")

    @field_validator("screen")
    @classmethod
    def _check_screen(cls, value: Any) -> Any:
        return value if value is None else _valid_matcher(value, "screen: ")


class Count(_Strict):
    """How many matching entries or items there must be."""

    min: int | None = Field(default=None, ge=0)
    max: int | None = Field(default=None, ge=0)

    @model_validator(mode="after")
    def _ordered(self) -> Count:
        if self.min is not None and self.max is not None and self.min > self.max:
            raise ValueError(f"min {self.min} is greater than max {self.max}")
        return self

    def allows(self, number: int) -> bool:
        """Whether ``number`` is within the bounds."""
        return (self.min is None or number >= self.min) and (self.max is None or number <= self.max)

    def describe(self) -> str:
        """E.g. ``exactly 1``, ``at least 1``, ``between 1 and 2``."""
        if self.min == self.max:
            return f"exactly {self.min}"
        if self.max is None:
            return f"at least {self.min or 0}"
        if self.min is None or self.min == 0:
            return f"at most {self.max}"
        return f"between {self.min} and {self.max}"


def as_count(value: int | Count | None, default: Count) -> Count:
    """A count as written (a number means exactly that many) with a default."""
    if value is None:
        return default
    return Count(min=value, max=value) if isinstance(value, int) else value


class ActionCheck(ActionPattern):
    """Such an action happened (at least once, or ``count`` times)."""

    count: int | Count | None = Field(
        default=None, description="Exactly N, or {min, max}. Default: at least 1."
    )


Maker = Literal["assistant", "user"]


class StateCheck(_Strict):
    """A condition on the final state of the apps.

    ``path`` names a place in the state snapshot (``calendar.events``, ``shopping.cart``,
    ``apartment.saved``). Either ``value`` is a matcher for what is there, or the place is a collection
    whose items are filtered by ``where`` (field name to matcher) and counted against ``count``. With
    ``by``, only what that actor made counts: items where it set a field the check reads (the value, for
    ``value``), so the user's own work is never credited to the assistant; a limit on the count counts
    every item it had a hand in.
    """

    path: str = Field(description="Dotted path into the final state, starting with an app: calendar.events.")
    where: dict[str, Any] = Field(
        default_factory=dict,
        description="Item field to matcher; '_key': the item's key in a keyed collection (a file's path); "
        "'_text': all of the item's text fields read together (title, description, content, ...); "
        "'any_of': a list of such mappings, of which one must hold.",
    )
    count: int | Count | None = Field(
        default=None, description="Exactly N, or {min, max}. Default: at least 1."
    )
    value: Matcher | None = Field(default=None, description="A matcher for the value at the path itself.")
    by: Maker | None = Field(
        default=None,
        description="Count only what this actor made: items where it set a field the check reads (a "
        "limit counts every item it changed at all). Default: anyone (seed data and the world included).",
    )

    @field_validator("where")
    @classmethod
    def _check_where(cls, value: dict[str, Any]) -> dict[str, Any]:
        return _check_where(value)

    @model_validator(mode="after")
    def _one_form(self) -> StateCheck:
        if "value" in self.model_fields_set and (self.where or self.count is not None):
            raise ValueError("give either 'value' or 'where'/'count', not both")
        if "value" in self.model_fields_set:
            _valid_matcher(self.value, "value: ")
        return self


class JudgeCheck(_Strict):
    """Free text judged by a model against a criterion, with a deterministic fallback.

    The text is the argument ``field`` of the actions matched by ``action``; the check holds when one of
    them meets the criterion, or, with ``together`` (the default where ``action`` has ``to``), when all of
    them read as one text (an answer that may come in several messages) do. Without a judge model,
    ``fallback`` (a matcher on the same text) decides.
    """

    criterion: str = Field(min_length=1, description="What the text must do, for the judge model.")
    action: ActionPattern = Field(description="Which actions carry the text.")
    field: str = Field(default="content", description="The argument holding the text.")
    together: bool | None = Field(
        default=None,
        description="Judge the texts of all matched actions as one (in the order they were made), for an "
        "answer that may be split over several messages; false judges each alone and one must pass. By "
        "default, together where the action names who was told ('to': what a person knows is everything "
        "they were told, so facts split over two messages count and a contradicting one counts against), "
        "else each alone.",
    )
    fallback: Matcher = Field(description="A matcher on the text, used when no judge model is configured.")
    facts: list[str] = Field(
        default_factory=list,
        description="What is true in the scenario, given to the judge model with the text, so it can tell "
        "an invented detail (a time, place or number these contradict or lack) from a right one. The "
        "fallback reads them too: a time, day, amount, phone number, link or email address of a kind they "
        "give, which neither they, the criterion nor the solutions' texts state, fails the text.",
    )
    optional: bool = Field(
        default=False,
        description="Sending is optional: the check holds when no action matches, and what is sent must "
        "meet the criterion (a courtesy message that, if sent, must be true). Not a positive check.",
    )
    other_details: str | None = Field(
        default=None,
        min_length=1,
        description="Why this check's text may state times, dates, amounts, phone numbers, links or email "
        "addresses its facts do not give (a note copying a whole timetable). Without it, the fallback "
        "fails a text stating a detail of a kind the facts give that neither they, the criterion nor the "
        "oracle's and passing variants' texts state.",
    )

    @field_validator("fallback")
    @classmethod
    def _check_fallback(cls, value: Any) -> Any:
        return _valid_matcher(value)

    @field_validator("facts")
    @classmethod
    def _check_facts(cls, value: list[str]) -> list[str]:
        return _checked_facts(value)

    @model_validator(mode="before")
    @classmethod
    def _together_where_told(cls, data: Any) -> Any:
        # decided once, here: a check without 'to' dumps (and hashes) as before the default changed
        if isinstance(data, dict) and data.get("together") is None:
            action = data.get("action")
            told = action.get("to") if isinstance(action, dict) else getattr(action, "to", None)
            data = {**data, "together": told is not None}
        return data

    @model_serializer(mode="wrap")
    def _dump(self, handler: SerializerFunctionWrapHandler) -> dict[str, Any]:
        data = _without_unused(_without_unused(handler(self), "facts", self.facts), "optional", self.optional)
        return _without_unused(data, "other_details", self.other_details)


def _without_unused(data: dict[str, Any], name: str, value: object) -> dict[str, Any]:
    """``data`` without the field ``name`` when it is unused (``value`` empty): a scenario that does not
    use a newer field dumps as before, so its content hash, which run folders keep, stays the same.
    """
    if not value:
        data.pop(name, None)
    return data


def _checked_facts(value: list[str]) -> list[str]:
    """A judge's facts, trimmed: each a non-empty sentence, none said twice."""
    seen: set[str] = set()
    for index, fact in enumerate(value):
        if not fact.strip():
            raise ValueError(f"facts[{index}] is empty: write each fact as a sentence")
        if fact.strip().casefold() in seen:
            raise ValueError(f"facts[{index}] repeats an earlier fact: {fact.strip()!r}")
        seen.add(fact.strip().casefold())
    return [fact.strip() for fact in value]


class Check(_Strict):
    """One check; exactly one of its forms is given."""

    # A form is a field here (its key in a scenario file, and its model) and a CheckForm registered under
    # the same key in pare.scenarios.checks (its rule). The docstring is the schema's description.

    action: ActionCheck | None = Field(default=None, description="An action that must have happened.")
    no_action: ActionPattern | None = Field(
        default=None, description="An action that must not have happened."
    )
    state: StateCheck | None = Field(default=None, description="A condition on the final state.")
    judge: JudgeCheck | None = Field(default=None, description="Model-judged free text with a fallback.")
    any_of: AnyOfChecks | None = Field(
        default=None,
        description="Checks of which one must hold: a choice the story leaves open, each way checked whole "
        "(the note ticks the liner off and the order holds it, or the note leaves it open).",
    )
    description: str = Field(default="", description="What the check means, for reports.")

    @model_validator(mode="after")
    def _exactly_one(self) -> Check:
        given = [name for name in CHECK_FORM_KEYS if getattr(self, name) is not None]
        if len(given) != 1:
            raise ValueError(
                f"a check has exactly one of {', '.join(CHECK_FORM_KEYS)}"
                + (f"; this one has {given}" if given else "")
            )
        return self

    @property
    def form(self) -> str:
        """Which form the check takes (its key): ``action``, ``no_action``, ``state`` or ``judge``."""
        return next(name for name in CHECK_FORM_KEYS if getattr(self, name) is not None)

    @property
    def body(self) -> BaseModel:
        """The check's part of its form (``self.action`` for an action check, ...)."""
        body: BaseModel = getattr(self, self.form)
        return body

    def leaves(self) -> Iterator[Check]:
        """The checks that read the apps: the check itself, or for an ``any_of`` those of its ways."""
        if self.any_of is None:
            yield self
            return
        for way in self.any_of.root:
            for check in way.all_of:
                yield from check.leaves()


class AnyOf(_Strict):
    """One way of meeting an ``any_of`` check: all its checks hold."""

    all_of: list[Check] = Field(min_length=1, description="The checks of this way, all of which must hold.")


class AnyOfChecks(RootModel[list[AnyOf]]):
    """The ways of an ``any_of`` check (at least two); one of them must hold, all its checks together."""

    @model_validator(mode="after")
    def _ways(self) -> AnyOfChecks:
        if len(self.root) < 2:
            raise ValueError("'any_of' needs at least two ways (each an 'all_of' list of checks)")
        for way in self.root:
            for check in way.all_of:
                if check.judge is not None:
                    raise ValueError(
                        "a judge check cannot stand inside 'any_of' (the judge is asked for the goals' own "
                        "judge checks): put it beside the any_of, 'optional: true' if it may be absent"
                    )
        return self


Check.model_rebuild()

CHECK_FORM_KEYS: tuple[str, ...] = tuple(name for name in Check.model_fields if name != "description")
"""The forms of check, by their keys: the fields of :class:`Check` but its description. Each form's rule
is registered in :data:`pare.scenarios.checks.CHECK_FORMS`."""


class Goal(_Strict):
    """One of the user's goals; it is met when all its checks hold."""

    id: str = Field(pattern=_ID.pattern)
    description: str = Field(min_length=1)
    checks: list[Check] = Field(min_length=1)


class Condition(_Strict):
    """Something that has happened by now: an event fired, and/or a matching action was logged."""

    event: str | None = Field(default=None, description="This scheduled event has fired.")
    action: ActionPattern | None = Field(default=None, description="A matching action has been logged.")

    @model_validator(mode="after")
    def _something(self) -> Condition:
        if self.event is None and self.action is None:
            raise ValueError("a condition needs 'event' or 'action' (or both)")
        return self


class Reaction(_Strict):
    """What the world does instead when a reactive event's trigger does not meet its ``if_args``: a reply
    that corrects or declines. Without one, the world stays silent.
    """

    id: str | None = Field(default=None, description="Its event id; default: '<event id>_otherwise'.")
    delay: DurationText | None = Field(default=None, description="Default: the event's own delay.")
    tool: str = Field(description="The tool as app__tool, e.g. email__receive_email.")
    args: dict[str, Any] = Field(default_factory=dict)

    @field_validator("delay")
    @classmethod
    def _duration(cls, value: str | int | None) -> str | int | None:
        if value is not None:
            try:
                parse_duration(value)
            except TimeFormatError as error:
                raise ValueError(str(error)) from None
        return value


class EventJudge(_Strict):
    """What a reactive event's triggering text must mean, asked of the run's judge model."""

    criterion: str = Field(
        min_length=1, description="What the triggering text must say for the event to fire, for the judge."
    )
    field: str = Field(
        default="content",
        description="The argument holding the text; 'if_args' tests it too (the rule used without a judge).",
    )
    facts: list[str] = Field(default_factory=list, description="What is true, as for a judge check.")

    @field_validator("facts")
    @classmethod
    def _check_facts(cls, value: list[str]) -> list[str]:
        return _checked_facts(value)


class Event(_Strict):
    """A call the world makes (an email arriving), and when.

    Exactly one of ``at`` (a time), ``after`` (another event's id) or ``when`` (the first matching
    action, by whoever) says when; ``delay`` shifts ``after`` and ``when``. A reactive event (``when``)
    can react to what was written: it fires on the first triggering action whose arguments meet
    ``if_args``; a triggering action that does not meet them gets the ``otherwise`` reaction (once, and
    only while the event has not fired), or silence.
    """

    id: str = Field(min_length=1)
    at: TimeText | None = None
    after: str | None = None
    when: ActionPattern | None = None
    if_args: dict[str, Matcher] = Field(
        default_factory=dict,
        description="With 'when': argument matchers the triggering action must meet for this event to fire "
        "(what was written: the question asked, the day proposed).",
    )
    otherwise: Reaction | None = Field(
        default=None,
        description="With 'if_args': what the world does when a triggering action does not meet them.",
    )
    judge: EventJudge | None = Field(
        default=None,
        description="With 'if_args': when the run has a judge model, it reads the triggering text against "
        "this criterion in place of the if_args matcher on that field; without one, the matcher decides.",
    )
    delay: DurationText = "0"
    tool: str = Field(description="The tool as app__tool, e.g. email__receive_email.")
    args: dict[str, Any] = Field(default_factory=dict)

    @field_validator("if_args")
    @classmethod
    def _check_if_args(cls, value: dict[str, Any]) -> dict[str, Any]:
        return _check_matchers(value)

    @model_serializer(mode="wrap")
    def _dump(self, handler: SerializerFunctionWrapHandler) -> dict[str, Any]:
        return _without_unused(handler(self), "judge", self.judge)

    @property
    def otherwise_id(self) -> str | None:
        """The event id of the ``otherwise`` reaction, if there is one."""
        if self.otherwise is None:
            return None
        return self.otherwise.id or f"{self.id}_otherwise"

    @field_validator("delay")
    @classmethod
    def _duration(cls, value: str | int) -> str | int:
        try:
            parse_duration(value)
        except TimeFormatError as error:
            raise ValueError(str(error)) from None
        return value

    @field_validator("at")
    @classmethod
    def _time(cls, value: str | None) -> str | None:
        if value is not None:
            try:
                parse_time(value, datetime(2000, 1, 1, tzinfo=UTC))
            except TimeFormatError as error:
                raise ValueError(str(error)) from None
        return value

    @model_validator(mode="after")
    def _one_trigger(self) -> Event:
        given = [name for name in ("at", "after", "when") if getattr(self, name) is not None]
        if len(given) != 1:
            raise ValueError(
                "an event has exactly one of 'at', 'after' or 'when'"
                + (f"; this one has {given}" if given else "")
            )
        if self.at is not None and "delay" in self.model_fields_set:
            raise ValueError("'delay' goes with 'after' or 'when'; with 'at', write the time itself")
        if self.if_args and self.when is None:
            raise ValueError("'if_args' goes with 'when': it tests the action that triggers the event")
        if self.judge is not None and self.judge.field not in self.if_args:
            field = self.judge.field
            raise ValueError(
                f"'judge' reads '{field}', which 'if_args' does not test: give if_args a matcher on "
                f"'{field}', the rule used when the run has no judge model"
            )
        if self.otherwise is not None and not self.if_args:
            raise ValueError("'otherwise' goes with 'if_args': it is what happens when they are not met")
        return self


class UserStep(_Strict):
    """An action the oracle user takes (by its name on the screen), once ``when`` holds. ``id`` names its
    result for later steps of the same list, as an oracle action's does (``${payee.id}`` for the id of
    the payee the step added).
    """

    id: str | None = None
    tool: str = Field(description="The action's name as the user sees it: open_app, open_email, ...")
    args: dict[str, Any] = Field(default_factory=dict)
    when: Condition | None = None


class OracleAction(_Strict):
    """An action the oracle assistant takes in execute mode. ``id`` names its result for later
    arguments written ``${id.field}`` (``${rem.id}`` for the id a write made), or ``${id}`` for the whole
    result.
    """

    id: str | None = None
    tool: str = Field(description="The tool as app__tool.")
    args: dict[str, Any] = Field(default_factory=dict)


class Intervention(_Strict):
    """What a perfect assistant does: propose once ``when`` holds, then, once accepted, act and report."""

    when: Condition | None = Field(default=None, description="Propose once this holds; at once if omitted.")
    proposal: str = Field(min_length=1, description="The proposal, as specific as a strict user expects.")
    answer: str = Field(default="Yes, please do that.", description="The oracle user's acceptance message.")
    actions: list[OracleAction] = Field(default_factory=list, description="Execute-mode actions, in order.")
    report: str = Field(default="Done.", min_length=1, description="The message reporting the task done.")


class Oracle(_Strict):
    """The scenario's solution: the user's own steps and the assistant's interventions; and how the user
    would do the task alone.
    """

    user: list[UserStep] = Field(default_factory=list, description="The user's scripted steps, in order.")
    interventions: list[Intervention] = Field(
        default_factory=list,
        description="The assistant's proposals, in order (none in a no_proposal scenario).",
    )
    by_hand: list[UserStep] = Field(
        default_factory=list,
        description="The user doing the task through the screens while the assistant stays silent: the "
        "self-test demands that this fails (the assistant's work is what is judged).",
    )


VERDICT_PARTS = ("side_effects", "invented_details")
"""What a variant's ``fails`` may name besides goals: the parts of the verdict that are no goal."""


class Variant(_Strict):
    """Another solution the checks must judge as declared: a correct one written differently (another
    tool, order, wording or artefact) that must pass, or a tempting near-miss that must fail.

    ``interventions`` and ``user`` replace the oracle's (YAML anchors let a variant reuse them).
    """

    id: str = Field(pattern=_ID.pattern)
    expect: Literal["pass", "fail"] = Field(description="The verdict the checks must give.")
    why: str = Field(min_length=1, description="One line: why this verdict is right.")
    interventions: list[Intervention] | None = Field(
        default=None, description="The assistant's interventions in this variant; default: the oracle's."
    )
    user: list[UserStep] | None = Field(
        default=None, description="The user's steps in this variant; default: the oracle's."
    )
    fails: list[str] = Field(
        default_factory=list,
        description="For expect: fail, the goals that must be the ones failed (so a near-miss fails for the "
        "reason it was written for, not by accident); 'side_effects' or 'invented_details' where it must "
        "fail through a change no solution makes or a detail nothing gives.",
    )
    otherwise_ok: dict[str, Annotated[str, Field(min_length=1)]] = Field(
        default_factory=dict,
        description="For expect: pass, the reactive events whose 'otherwise' reply this solution gets on "
        "purpose (a first message that asks or says too little, then the full answer once the world asks "
        "back), each with why that is fine. The gate fails a passing variant that the world answered with "
        "an 'otherwise' branch not named here.",
    )
    held_out: bool = Field(
        default=False,
        description="A reviewer's probe, not one of the scenario's solutions: it is judged like any variant, "
        "but a passing one teaches the checks nothing (the details its texts state are not allowed by that, "
        "its changes do not widen the side-effect envelope, the strict user does not learn its proposals), "
        "so its verdict is the one a real assistant doing the same would get.",
    )

    @property
    def teaches(self) -> bool:
        """Whether this variant is one of the scenario's right solutions, which define what is allowed."""
        return self.expect == "pass" and not self.held_out

    @model_validator(mode="after")
    def _differs(self) -> Variant:
        if self.interventions is None and self.user is None:
            raise ValueError("a variant gives 'interventions' or 'user' (or both): what it does differently")
        if self.fails and self.expect == "pass":
            raise ValueError("'fails' names the goals a failing variant fails; this variant must pass")
        if self.otherwise_ok and self.expect == "fail":
            raise ValueError(
                "'otherwise_ok' excuses a correct solution that gets an 'otherwise' reply; a failing "
                "variant may get any reply"
            )
        return self


@dataclass(frozen=True, slots=True)
class Solution:
    """What the oracle policies play: the user's steps and the assistant's interventions."""

    name: str
    user: tuple[UserStep, ...]
    interventions: tuple[Intervention, ...]


ChangeKind = Literal["added", "changed", "removed", "sent"]
"""How the assistant changed the apps' data: a new item, an existing item changed or removed, or something
sent to a person (an email, a message, an invitation)."""


class AllowedChange(_Strict):
    """A change the assistant may make beyond what the scenario's solutions make, and why it is harmless
    (see :mod:`pare.scenarios.side_effects`).
    """

    app: str = Field(description="The app whose data changes.")
    collection: str | None = Field(
        default=None,
        description="The top-level field of the app's data (events, emails, notes); default: any. Not for "
        "'sent', which names a person whatever the app.",
    )
    change: ChangeKind = Field(
        description="added: a new item; changed or removed: an existing item (the two are one allowance); "
        "sent: an email, message or invitation to a person."
    )
    target: str | None = Field(
        default=None,
        description="Which one: the existing item's key (changed, removed), the person's name or address "
        "(sent), the key of a new entry in a collection of plain values (added: a cart's item id); default: "
        "any, and for added any number of new items.",
    )
    reason: str = Field(min_length=1, description="Why this change is harmless to the user.")

    @model_validator(mode="after")
    def _sent_is_about_people(self) -> AllowedChange:
        if self.change == "sent" and self.collection is not None:
            raise ValueError("'sent' names a person, not a collection: drop 'collection'")
        return self


MUTANT_OPERATORS = (
    "swap_person",
    "shift_time",
    "shift_text_time",
    "drop_action",
    "send_as_draft",
    "extra_write",
    "swap_item",
    "change_number",
    "swap_file",
    "other_slot",
    "similar_item",
    "early_proposal",
)
"""The operators of :mod:`pare.scenarios.mutants` whose mutants the checks must fail."""
REWRITE_OPERATORS = (
    "reorder",
    "time_phrasing",
    "date_phrasing",
    "split_message",
    "reply_as_new",
    "new_as_reply",
    "delete_readd",
    "rename_file",
)
"""The operators of :mod:`pare.scenarios.mutants` whose rewrites the checks must pass."""


def _mutant_names(value: dict[str, str]) -> dict[str, str]:
    for name in value:
        operator, colon, where = name.partition(":")
        if not colon or not where:
            raise ValueError(
                f"'{name}' is not a mutant's name; write <operator>:<where>, e.g. drop_action:1.2"
            )
        if operator not in MUTANT_OPERATORS:
            raise ValueError(
                f"'{name}': unknown mutant operator '{operator}'.{did_you_mean(operator, MUTANT_OPERATORS)} "
                f"Operators: {', '.join(MUTANT_OPERATORS)} (a rewrite must pass; it is never declared)"
            )
    return value


DetailKind = Literal["time", "date", "money", "phone", "url", "email"]
"""A kind of detail a program reads reliably in free text (:mod:`pare.scenarios.fact_details`)."""


class InventedDetailsAllowance(_Strict):
    """Kinds of detail the assistant may state without a text of the scenario giving them, and why (see
    :mod:`pare.scenarios.invented`).
    """

    allow: list[DetailKind] = Field(min_length=1, description="The kinds of detail not checked.")
    reason: str = Field(min_length=1, description="Why the story asks the assistant for new values of them.")


class UserProfile(_Strict):
    """What the user simulator is told about the person it plays."""

    goal: str | None = Field(
        default=None, description="A hidden goal the user has (never told the assistant)."
    )
    persona: str | None = Field(default=None, description="Who the user is and how readily they trust help.")


class Scenario(_Strict):
    """A PARE-Bench scenario."""

    format: Literal[1] = Field(default=1, description="Version of the scenario file format.")
    id: str = Field(
        pattern=_ID.pattern,
        max_length=MAX_SCENARIO_ID_LENGTH,
        description=f"Lowercase words joined by underscores; at most {MAX_SCENARIO_ID_LENGTH} characters (it "
        "names the scenario's file).",
    )
    title: str = Field(min_length=1)
    story: str = Field(min_length=1, description="The situation in a few sentences.")
    tags: list[Tag] = Field(min_length=1)
    difficulty: Difficulty
    kind: Literal["proposal", "no_proposal"] = Field(
        default="proposal",
        description="'no_proposal': the right move is not to propose (a notification that needs nothing, a "
        "plan still open, a task the user is doing); the gate turns round: the watchful silent assistant "
        "passes and an eager one fails.",
    )
    end_when_met: bool = Field(
        default=False,
        description="End the episode once every goal is met while the user and the assistant both wait "
        "and no proposal is pending: what is still to come (a later event, a reminder falling due) cannot "
        "change the verdict, so playing on to the turn limit only spends model calls. Decided with the "
        "judge checks' deterministic fallbacks. Not for no_proposal scenarios, whose goals hold from the "
        "start.",
    )
    apps: list[str] = Field(min_length=1, description="The apps on the phone besides the core ones.")
    start: datetime = Field(description="When the episode starts (UTC if no zone is given).")
    user: UserProfile = Field(default_factory=UserProfile)
    seed: dict[str, dict[str, Any]] = Field(default_factory=dict, description="Seed data per app.")
    events: list[Event] = Field(default_factory=list)
    oracle: Oracle
    goals: list[Goal] = Field(min_length=1)
    variants: list[Variant] = Field(
        default_factory=list,
        description="Other solutions with the verdict the checks must give them (proven by the gate).",
    )
    allowed_changes: list[AllowedChange] = Field(
        default_factory=list,
        description="Harmless changes the assistant may make beyond what the oracle and the passing "
        "variants change, each with its reason; any other change of the assistant's is a side effect and "
        "fails the episode.",
    )

    invented_details: InventedDetailsAllowance | None = Field(
        default=None,
        description="Kinds of detail (time, date, money, phone, url, email) the assistant may state in "
        "what it writes into the apps although no text of the scenario gives them, with the reason (the "
        "story asks it to compute new values); any other such detail is invented and fails the episode.",
    )

    equivalent_mutants: dict[str, Annotated[str, Field(min_length=1)]] = Field(
        default_factory=dict,
        description="Generated mutants of the oracle (pare scenarios check --mutants -v names them) that are "
        "right after all, each with the reason a reviewer would accept: the gate counts them as declared, "
        "not as surviving.",
    )

    @field_validator("equivalent_mutants")
    @classmethod
    def _known_mutants(cls, value: dict[str, str]) -> dict[str, str]:
        return _mutant_names(value)

    @field_validator("start")
    @classmethod
    def _utc(cls, value: datetime) -> datetime:
        return value if value.tzinfo else value.replace(tzinfo=UTC)

    @field_validator("tags", "apps")
    @classmethod
    def _unique(cls, values: list[str]) -> list[str]:
        repeated = sorted({v for v in values if values.count(v) > 1})
        if repeated:
            raise ValueError(f"listed more than once: {', '.join(repeated)}")
        return values

    @field_validator("apps")
    @classmethod
    def _known_apps(cls, values: list[str]) -> list[str]:
        known = phone_apps()
        for app in values:
            if app in ("system", "agent_ui"):
                raise ValueError(f"'{app}' is part of every phone; do not list it")
            if app not in known:
                raise ValueError(f"unknown app '{app}'.{did_you_mean(app, known)} Apps: {', '.join(known)}")
        return values

    def solution(self, variant: str | None = None) -> Solution:
        """The oracle's solution, or a variant's (its steps and interventions, the oracle's by default)."""
        if variant is None:
            return Solution("oracle", tuple(self.oracle.user), tuple(self.oracle.interventions))
        for candidate in self.variants:
            if candidate.id == variant:
                user = self.oracle.user if candidate.user is None else candidate.user
                interventions = (
                    self.oracle.interventions if candidate.interventions is None else candidate.interventions
                )
                return Solution(candidate.id, tuple(user), tuple(interventions))
        raise KeyError(variant)

    def change_allowances(self) -> list[AllowedChange]:
        """The changes allowed beyond the solutions': ``allowed_changes``, and a message to each person an
        optional judge check reads what is sent to (by declaring what such a message must say, the check
        declares that it may be sent, and judges it).
        """
        implied = [
            AllowedChange(
                app="any",
                change="sent",
                target=person,
                reason=f"goal '{goal.id}' judges whatever is sent to {person} (an optional judge check)",
            )
            for goal in self.goals
            for check in goal.checks
            if check.judge is not None and check.judge.optional and check.judge.action.to is not None
            for person in (
                [check.judge.action.to] if isinstance(check.judge.action.to, str) else check.judge.action.to
            )
        ]
        return [*self.allowed_changes, *implied]

    def right_solutions(self) -> list[str | None]:
        """The solutions that define what is right: the oracle (``None``) and each passing variant that is
        not a held-out probe, in the scenario's order.
        """
        return [None, *(variant.id for variant in self.variants if variant.teaches)]

    def by_hand(self) -> Solution:
        """The user doing the task alone through the screens (no interventions)."""
        return Solution("by_hand", tuple(self.oracle.by_hand), ())

    @property
    def all_apps(self) -> list[str]:
        """The scenario's apps plus Files when it is seeded (the core apps are always present)."""
        return [*self.apps, *(["files"] if "files" in self.seed and "files" not in self.apps else [])]

    def content_hash(self) -> str:
        """A hash of the scenario's content: the same data gives the same hash, whatever the file's layout
        (a run folder tells by it that a scenario changed). A scenario read from the parsed-scenario cache
        carries the hash computed when it was stored.
        """
        known = self.__dict__.get(_KNOWN_HASH)
        if isinstance(known, str):
            return known
        dumped = self.model_dump(mode="json")
        later_fields = ("allowed_changes", "equivalent_mutants", "invented_details")
        for later in later_fields:  # fields added later: scenarios without
            if not dumped.get(later):  # them keep their hash
                dumped.pop(later, None)
        data = json.dumps(dumped, sort_keys=True, separators=(",", ":"))
        return hashlib.sha256(data.encode("utf-8")).hexdigest()[:16]

    # -- variants read when first asked for ---------------------------------------------------------------
    # Only the gate and the review read a scenario's variants, and validating them is most of validating a
    # cached scenario: a scenario from the parsed-scenario cache validates them when ``variants`` is first
    # read. Until then the field is missing from ``__dict__`` (Python then calls ``__getattr__``); whatever
    # reads ``__dict__`` itself (dumping, comparing, ``repr``) completes the scenario first.
    @classmethod
    def with_deferred_variants(
        cls, data: dict[str, Any], variants: Callable[[], list[Variant]] | None, content_hash: str
    ) -> Scenario:
        """The scenario of ``data`` (a valid scenario's fields but its variants) with the variants that
        ``variants()`` gives, validated (``None``: none written), and its :meth:`content_hash`, both as
        stored for it.
        """
        scenario = cls.model_validate(data)
        scenario.__dict__[_KNOWN_HASH] = content_hash
        if variants is not None:
            del scenario.__dict__["variants"]
            scenario.__pydantic_fields_set__.add("variants")
            scenario.__dict__[_PENDING_VARIANTS] = variants
        return scenario

    def _complete(self) -> None:
        read = self.__dict__.get(_PENDING_VARIANTS)
        if read is not None:
            self.__dict__["variants"] = read()
            self.__dict__.pop(_PENDING_VARIANTS, None)

    if not TYPE_CHECKING:  # as pydantic does: a visible ``__getattr__`` would let mypy pass any attribute

        def __getattr__(self, name: str) -> Any:
            if name == "variants" and _PENDING_VARIANTS in self.__dict__:
                self._complete()
                return self.__dict__["variants"]
            return super().__getattr__(name)

    def model_dump(self, **options: Any) -> dict[str, Any]:
        """As BaseModel's."""
        self._complete()
        return super().model_dump(**options)

    def model_dump_json(self, **options: Any) -> str:
        """As BaseModel's."""
        self._complete()
        return super().model_dump_json(**options)

    def model_copy(self, *, update: Mapping[str, Any] | None = None, deep: bool = False) -> Scenario:
        """A copy (see BaseModel's); one with fields updated computes its :meth:`content_hash` afresh."""
        self._complete()
        copy = super().model_copy(update=update, deep=deep)
        if update:
            copy.__dict__.pop(_KNOWN_HASH, None)
        return copy

    def __eq__(self, other: object) -> bool:
        self._complete()
        if isinstance(other, Scenario):
            other._complete()
        return super().__eq__(other)

    def __repr_args__(self) -> Any:
        self._complete()
        return super().__repr_args__()


_KNOWN_HASH = "_content_hash"
"""Key in a scenario's ``__dict__`` (not a field) of its :meth:`Scenario.content_hash` read from the cache."""
_PENDING_VARIANTS = "_pending_variants"
"""Key in a scenario's ``__dict__`` (not a field) of what gives its variants, before they are validated."""


def validate_variants(raw: Any) -> list[Variant]:
    """``raw`` validated as a scenario's ``variants``."""
    return _variant_list().validate_python(raw)


@functools.cache
def _variant_list() -> TypeAdapter[list[Variant]]:
    return TypeAdapter(list[Variant])
