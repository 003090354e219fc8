"""The trajectory: everything one episode did, as ``pare run`` stores it and everything else reads it.

One file per complete episode (``trajectories/<scenario>/run-<r>.json`` in a run folder), written by
:func:`write_trajectory` and read by :func:`read_trajectory`; nothing else parses these files. The shape
is the :class:`Trajectory` model, versioned by its ``format``:

* **format 2** (this one): the steps (each user step with the phone as the user saw it), the action log,
  the whole attribution (each place's creator, last changer and every actor that had a hand in it, and
  what was removed), the verdict, the state diff from start to end, the proposals with what became of
  them (and the turn an expired one expired in), the content hash of the apps' data at the start, the
  replies delivered after the last turn and each model-backed actor's closing observation;
* **format 1** (files written before): no proposals (only the ids of the expired ones), no start hash,
  the attribution's marks by dotted place without who else had a hand and what was removed; user steps
  without the phone's view in the oldest files. It is upgraded on read (:func:`upgrade_format_1`): what
  it lacks stays unknown (``expired_at``, ``start_state_hash``, ``hands``, ``removals`` are ``None``).

A file of a newer format than this PARE knows is refused, named, with the format it has. Within a
format, the verdicts' parts (goals, checks, side effects) may carry fields this reader does not know;
they are kept as they are.

Re-grading evaluates the checks again on the log, the attribution (:meth:`Trajectory.attribution_state`)
and the apps' final state. The final state is not stored: it is the start (rebuilt from the scenario)
with the state diff applied, and :func:`final_state` checks that the start rebuilt is the one the
episode started from (``start_state_hash``). Storing it would make every trajectory much larger for
what the scenario and the diff already give (docs/architecture.md, "The trajectory").
"""

from __future__ import annotations

import copy
import hashlib
import json
from collections.abc import Mapping
from datetime import datetime
from functools import cached_property
from pathlib import Path
from typing import Any, Literal, get_args

import jsonpatch
from pydantic import BaseModel, ConfigDict, Field, ValidationError
from pydantic_core import PydanticSerializationError, to_json

from pare.agents.models.ledger import StepUsage
from pare.agents.policy import SEND_MESSAGE
from pare.apps.agent_ui import ProposalStatus
from pare.env.attribution import Attribution, Mark
from pare.errors import UserInputError
from pare.sim.log import Actor, AssistantMode, LogEntry, ToolKind
from pare.yaml_source import UnreadableFile, read_text_file

TRAJECTORY_FORMAT: Literal[2] = 2
"""The format this PARE writes; it reads this one and every older one."""
MAX_TRAJECTORY_BYTES = 64 * 1024 * 1024
"""The largest trajectory file read (a long model-backed episode is a few hundred KB)."""

StepActor = Literal["user", "assistant"]
ANSWERS: dict[str, Literal["accept", "reject"]] = {"accept_proposal": "accept", "reject_proposal": "reject"}
"""The user's tools that answer a proposal, and the answer each gives."""


# NaN and infinity are written as the constants JSON does not have, so that :func:`write_trajectory` finds
# them (a value no JSON file can hold fails its episode, rather than becoming ``null`` unseen).
class _Part(BaseModel):
    """A part of the trajectory this PARE writes in full: a field it does not know is damage."""

    model_config = ConfigDict(extra="forbid", frozen=True, allow_inf_nan=False, ser_json_inf_nan="constants")


class _Verdict(BaseModel):
    """A part of the verdict: its checks may gain fields within a format, kept as they are."""

    model_config = ConfigDict(extra="allow", frozen=True, allow_inf_nan=False, ser_json_inf_nan="constants")


class ActionRecord(_Part):
    """What an actor chose: the tool under the actor's name for it, the arguments, and for a model, what
    it wrote and what the calls behind it cost.
    """

    tool: str
    args: dict[str, Any] = Field(default_factory=dict)
    raw: str | None = None
    error: str | None = None
    usage: StepUsage | None = None
    reasoning: str | None = None


class ViewRecord(_Part):
    """The phone as the user saw it before a step (see ``pare.bench.episode.view_record``)."""

    time: str
    app: str | None = None
    screen: str | None = None
    background_apps: list[str] = Field(default_factory=list)
    screen_update: Any = None
    notifications: list[str] = Field(default_factory=list)
    pending_proposal: str | None = None
    tools: list[str] = Field(default_factory=list)
    proposal_turns_left: int | None = None
    clock_jump: str | None = None


class StepRecord(_Part):
    """One action of one actor and what came of it."""

    turn: int
    actor: StepActor
    mode: AssistantMode | None = None
    action: ActionRecord
    ok: bool
    observation: str
    log_index: int | None = None
    view: ViewRecord | None = None
    """For a user step, the phone before it (``None`` in the oldest files, and for the assistant)."""


class LogRecord(_Part):
    """One action-log entry as stored; :meth:`entry` is the kernel's own :class:`LogEntry`."""

    index: int
    turn: int
    time: datetime
    actor: Actor
    app: str
    tool: str
    args: dict[str, Any] = Field(default_factory=dict)
    kind: ToolKind | None = None
    ok: bool
    result: Any = None
    error: str | None = None
    mode: AssistantMode | None = None
    injected_failure: bool = False
    event_id: str | None = None
    screen: str | None = None

    def entry(self) -> LogEntry:
        """The entry as the checks and patterns read it."""
        return LogEntry(
            index=self.index,
            turn=self.turn,
            time=self.time,
            actor=self.actor,
            app=self.app,
            tool=self.tool,
            args=self.args,
            kind=self.kind,
            ok=self.ok,
            result=self.result,
            error=self.error,
            mode=self.mode,
            injected_failure=self.injected_failure,
            event_id=self.event_id,
            screen=self.screen,
        )

    @property
    def proposal_id(self) -> str | None:
        """The proposal this call made or answered, when its result names one."""
        found = self.result.get("proposal_id") if isinstance(self.result, dict) else None
        return found if isinstance(found, str) else None


class PlaceRecord(_Part):
    """Who made one place of the apps' data (``pare.env.attribution.Mark``) and who had a hand in it."""

    place: tuple[str, ...] = Field(min_length=1, description="The place's path, items by their identity.")
    created_by: Actor | None = None
    changed_by: Actor
    created_at: int | None = None
    changed_at: int
    hands: dict[Actor, int] | None = Field(
        default=None,
        description="Every actor that created or changed it (or anything in it), with its latest call; "
        "``None`` in format-1 files, which did not keep it.",
    )

    @property
    def dotted(self) -> str:
        """The place as one string, ``calendar.events.ev-3`` (how format 1 named it)."""
        return ".".join(self.place)


class RemovalRecord(_Part):
    """A place an attributed actor removed: the last remover and its call."""

    place: tuple[str, ...] = Field(min_length=1)
    actor: Actor
    at: int


class JudgeVerdictRecord(_Verdict):
    """What a judge model said of one text: its verdict, its one-sentence reason, its whole answer."""

    passed: bool
    reason: str = ""
    answer: str = ""
    model: str = ""


class JudgedTextRecord(_Verdict):
    """One text a judge check gave the judge (the calls it is from) and the judge's verdict on it."""

    entries: list[int] = Field(default_factory=list)
    verdict: JudgeVerdictRecord


class CheckRecord(_Verdict):
    """One check's verdict and its sentence."""

    goal: str = ""
    index: int
    form: str
    passed: bool
    detail: str = ""
    description: str = ""
    user_made: bool = False
    judged: list[JudgedTextRecord] = Field(
        default_factory=list,
        description="The texts a judge model read for the check, with its answers (empty when none did, and "
        "in files written before judges' answers were kept).",
    )


class GoalRecord(_Verdict):
    """One goal and its checks."""

    id: str
    description: str = ""
    passed: bool
    checks: list[CheckRecord] = Field(default_factory=list)


class SideEffectRecord(_Verdict):
    """A change of the assistant's that no solution of the scenario makes."""

    app: str = ""
    collection: str = ""
    kind: str = ""
    target: str = ""
    detail: str = ""
    address: str = ""
    fields: list[str] = Field(
        default_factory=list, description="The fields it wrote that no solution writes."
    )
    lost: list[str] = Field(
        default_factory=list,
        description="Lines of the item's old text it dropped or altered that every solution keeps.",
    )
    harm: str | None = Field(
        default=None,
        description="The class of the tool whose call made it: reversible, costly, irreversible.",
    )
    order: int | None = Field(default=None, description="The log index of the call that made it.")
    quantity: int = Field(default=1, description="For a new item: how many of its shape beyond the envelope.")
    text: str = ""


class InventedRecord(_Verdict):
    """A detail the assistant wrote into the apps that nothing in its world gives
    (``pare.scenarios.invented``).
    """

    order: int | None = Field(default=None, description="The log index of the call that wrote it.")
    tool: str = Field(default="", description="The call, as app__tool.")
    target: str = Field(default="", description="Where the text went, as the call names it.")
    field: str = Field(default="", description="The argument holding the text.")
    kind: str = Field(
        default="",
        description="time, date, money, phone, url or email; also count, part_of_day, code, street, month, "
        "percent; or act: an act the text claims that no call of the episode did.",
    )
    shown: str = Field(default="", description="The detail as written.")
    excerpt: str = Field(default="", description="The words around it.")
    against: str = Field(
        default="nothing in the scenario",
        description="What does not give it: nothing in the scenario, or the story's facts (a detail the "
        "world gives somewhere, of a kind the facts give, that neither they nor a solution state).",
    )
    text: str = ""


class OutcomeRecord(_Verdict):
    """The verdict on the episode."""

    success: bool
    goal_rate: float = 0.0
    user_did_work: bool = False
    goals: list[GoalRecord] = Field(default_factory=list)
    side_effects: list[SideEffectRecord] = Field(default_factory=list)
    invented: list[InventedRecord] = Field(
        default_factory=list,
        description="Details the assistant invented (files written before the rule hold none).",
    )


class AfterLastTurnRecord(_Part):
    """The world's replies delivered after the last turn (``pare.bench.episode.AfterLastTurn``)."""

    model_config = ConfigDict(populate_by_name=True)

    turn: int
    start: str = Field(alias="from")
    until: str
    delivered: list[str] = Field(default_factory=list)
    beyond: list[str] = Field(default_factory=list)


class ProposalMade(_Part):
    """A proposal the assistant made and what finally became of it."""

    proposal_id: str
    turn: int = Field(description="The turn the assistant proposed in.")
    content: str
    status: ProposalStatus = Field(description="``pending``: still unanswered when the episode ended.")
    expired_at: int | None = Field(
        default=None,
        description="For an expired proposal, the turn it expired in (after the user's step of that turn); "
        "``None`` otherwise, and for expired proposals of format-1 files, which did not keep it.",
    )


FaultKind = Literal["accepted_wrong", "rejected_right", "did_by_hand", "stalled", "unseen_fact"]
"""What the user simulator did wrong on its own (see :mod:`pare.bench.simulator_faults` for each rule)."""
FAULT_KINDS: tuple[FaultKind, ...] = get_args(FaultKind)


class SimulatorFault(_Part):
    """Something the user simulator did wrong independently of the assistant, found when the episode ended."""

    kind: FaultKind
    turn: int = Field(description="The turn of the user's step at fault (or of the proposal it left).")
    detail: str = Field(description="What happened, in one sentence.")
    proposal_id: str | None = Field(default=None, description="The proposal concerned, if any.")


class Trajectory(_Part):
    """One episode as stored: what identifies it in its run, then what happened and the verdict."""

    format: Literal[2] = TRAJECTORY_FORMAT
    label: str = ""
    run: int = 1
    seed: int | None = None
    scenario_hash: str = ""
    scenario_id: str
    user: str = ""
    assistant: str = ""
    turns: int = 0
    ended: str = ""
    proposals: list[ProposalMade] = Field(default_factory=list)
    steps: list[StepRecord]
    log: list[LogRecord] = Field(default_factory=list)
    attribution: list[PlaceRecord] = Field(
        default_factory=list, description="Who made each place of the apps' data, in the order made."
    )
    removals: list[RemovalRecord] | None = Field(
        default=None, description="What the user or the assistant removed (``None``: a format-1 file)."
    )
    outcome: OutcomeRecord
    state_diff: list[dict[str, Any]] | None = Field(
        default=None,
        description="The apps' data from start to end as JSON Patch operations (``None``: oldest files).",
    )
    start_state_hash: str | None = Field(
        default=None, description="Content hash of the apps' data at the start (:func:`state_hash`)."
    )
    after_last_turn: AfterLastTurnRecord | None = None
    closing: dict[str, str] = Field(default_factory=dict)
    simulator_faults: list[SimulatorFault] = Field(
        default_factory=list,
        description="What the user simulator did wrong on its own (pare.bench.simulator_faults); empty in "
        "files written before faults were looked for.",
    )

    @cached_property
    def entries(self) -> dict[int, LogRecord]:
        """The log's entries by their own index (what steps, checks and attribution name)."""
        return {record.index: record for record in self.log}

    @cached_property
    def marks(self) -> dict[str, PlaceRecord]:
        """The attribution by dotted place (what the viewer matches the state diff's paths against)."""
        return {record.dotted: record for record in self.attribution}

    def attribution_state(self) -> Attribution:
        """The episode's attribution as the checks read it (re-grading evaluates them on it).

        Raises:
            ValueError: The file does not keep it whole (format 1: no hands, no removals).
        """
        if self.removals is None or any(record.hands is None for record in self.attribution):
            raise ValueError("the trajectory does not keep the whole attribution (written before format 2)")
        return Attribution.restored(
            {
                record.place: Mark(record.created_by, record.changed_by, record.created_at, record.changed_at)
                for record in self.attribution
            },
            {record.place: record.hands or {} for record in self.attribution},
            {record.place: (record.actor, record.at) for record in self.removals},
        )

    def log_entries(self) -> list[LogEntry]:
        """The action log as the kernel's entries, in order (what checks and patterns read)."""
        return [record.entry() for record in self.log]

    def expired_at(self) -> dict[str, int]:
        """The turn each expired proposal expired in (those whose turn is known)."""
        return {p.proposal_id: p.expired_at for p in self.proposals if p.expired_at is not None}


def attribution_records(attribution: Attribution) -> tuple[list[PlaceRecord], list[RemovalRecord]]:
    """The trajectory's form of an episode's attribution: its places and what was removed, in the order
    the episode made them (deterministic, and what :meth:`Trajectory.attribution_state` restores, so the
    side effects found again come in the same order).
    """
    places = [
        PlaceRecord(
            place=place,
            created_by=mark.created_by,
            changed_by=mark.changed_by,
            created_at=mark.created_at,
            changed_at=mark.changed_at,
            hands=dict(attribution.hands_of(place)),
        )
        for place, mark in attribution.marks().items()
    ]
    removals = [
        RemovalRecord(place=place, actor=actor, at=index)
        for place, (actor, index) in attribution.removals().items()
    ]
    return places, removals


def state_hash(state: Mapping[str, Any]) -> str:
    """A content hash of the apps' data, in the order PARE's snapshot gives it: the same code and data give
    the same order, and this runs for every episode stored, where sorting every key would not be cheap.
    """
    return hashlib.sha256(to_json(state, fallback=str)).hexdigest()[:32]


def final_state(trajectory: Trajectory, start: Mapping[str, Any]) -> dict[str, Any]:
    """The apps' data at the end of the episode: ``start`` (the scenario's world rebuilt) with the
    trajectory's state diff applied; ``start`` is not changed.

    Raises:
        ValueError: The trajectory has no state diff, ``start`` is not the start the episode had (its
            hash differs from ``start_state_hash``), or the diff does not apply to it.
    """
    if trajectory.state_diff is None:
        raise ValueError("the trajectory kept no state diff (written before PARE kept one)")
    if trajectory.start_state_hash is not None and state_hash(start) != trajectory.start_state_hash:
        raise ValueError(
            "the apps' data at the start is not the data this episode started from (the scenario's "
            "world changed since it ran)"
        )
    try:
        result: dict[str, Any] = jsonpatch.apply_patch(copy.deepcopy(dict(start)), trajectory.state_diff)
    except (jsonpatch.JsonPatchException, jsonpatch.JsonPointerException, TypeError, KeyError) as error:
        raise ValueError(f"the state diff does not apply to the start: {error}") from None
    return result


# -- writing ----------------------------------------------------------------------------------------------
def write_trajectory(trajectory: Trajectory) -> str:
    """The file's text: strict, compact JSON in valid UTF-8, the same bytes for the same trajectory.

    Raises:
        ValueError: A value no JSON file can hold (NaN, infinity, a lone surrogate): a bug upstream.
    """
    try:
        text = trajectory.model_dump_json(by_alias=True)
    except PydanticSerializationError as error:
        raise ValueError(f"the trajectory cannot be written as JSON: {error}") from None
    if "NaN" in text or "Infinity" in text:  # rare in any text: only then is the whole file parsed
        json.loads(text, parse_constant=_not_json)
    return text


def _not_json(constant: str) -> None:
    raise ValueError(f"the trajectory cannot be written as JSON: it holds {constant}, which JSON has not")


# -- reading ----------------------------------------------------------------------------------------------
def read_trajectory(file: Path, *, max_bytes: int = MAX_TRAJECTORY_BYTES) -> Trajectory:
    """The trajectory in ``file``, of this format or upgraded from an older one.

    Raises:
        UserInputError: The file cannot be read, is not JSON, is of a newer format than this PARE reads,
            or is damaged (the message names the file and the field).
    """
    try:
        text = read_text_file(file, max_bytes=max_bytes)
    except UnreadableFile as error:
        reason = str(error).removeprefix("cannot read it: ")
        raise UserInputError(f"{file}: cannot read the trajectory: {reason}") from None
    except OSError as error:
        raise UserInputError(f"{file}: cannot read the trajectory: {error.strerror or error}") from None
    return parse_trajectory(text, str(file))


def parse_trajectory(text: str, where: str = "trajectory") -> Trajectory:
    """A trajectory from its file's text (``where`` names it in errors); see :func:`read_trajectory`."""
    try:
        data = json.loads(text)
    except (json.JSONDecodeError, RecursionError) as error:
        raise UserInputError(f"{where}: not a trajectory (not JSON: {error})") from None
    if not isinstance(data, dict) or "steps" not in data:
        raise UserInputError(f"{where}: not a PARE trajectory (a JSON object with steps)")
    found = data.get("format", 1)  # files written before the number was kept are format 1
    if isinstance(found, bool) or not isinstance(found, int) or found < 1:
        raise UserInputError(
            f"{where}: trajectory format {found!r} is not a format number; the file is damaged"
        )
    if found > TRAJECTORY_FORMAT:
        raise UserInputError(
            f"{where}: trajectory format {found}, newer than this PARE reads (up to {TRAJECTORY_FORMAT}); "
            "read it with the PARE version that wrote it, or a newer one"
        )
    if found == 1:
        data = upgrade_format_1(data)
    try:
        return Trajectory.model_validate(data)
    except ValidationError as error:
        raise UserInputError(f"{where}: damaged trajectory: {_first_problem(error)}") from None


def _first_problem(error: ValidationError) -> str:
    problem = error.errors(include_url=False)[0]
    field = ".".join(str(part) for part in problem["loc"]) or "the whole file"
    return f"{field}: {problem['msg']}"


def upgrade_format_1(data: dict[str, Any]) -> dict[str, Any]:
    """A format-1 trajectory's data in format 2: the proposals are read back from the steps and the log
    (the turn an expired one expired in was not kept), the other fields are as they were. Damage is left
    for the model to name (a part that is not what format 1 wrote is passed on unchanged).
    """
    upgraded = {key: value for key, value in data.items() if key != "expired_proposals"}
    upgraded["format"] = 2
    marks = data.get("attribution")
    if isinstance(marks, dict):  # by dotted place; an id with a dot in it cannot be told apart here
        upgraded["attribution"] = [
            {"place": place.split("."), **mark} if isinstance(mark, dict) else mark
            for place, mark in marks.items()
        ]
    expired = data.get("expired_proposals") or []
    upgraded["proposals"] = _format_1_proposals(data, expired if isinstance(expired, list) else [])
    return upgraded


def _format_1_proposals(data: dict[str, Any], expired: list[Any]) -> list[dict[str, Any]]:
    """The proposals of a format-1 file: each observe-mode message that made one, and its answer."""
    log = data.get("log")
    steps = data.get("steps")
    if not isinstance(log, list) or not isinstance(steps, list):
        return []
    by_index = {entry.get("index"): entry for entry in log if isinstance(entry, dict)}
    answered: dict[str, ProposalStatus] = {}
    for entry in log:
        if not isinstance(entry, dict) or entry.get("app") != "agent_ui" or not entry.get("ok"):
            continue
        answer = ANSWERS.get(str(entry.get("tool")))
        result = entry.get("result")
        answered_id = result.get("proposal_id") if isinstance(result, dict) else None
        if answer is not None and isinstance(answered_id, str):
            answered.setdefault(answered_id, "accepted" if answer == "accept" else "rejected")
    proposals: list[dict[str, Any]] = []
    for step in steps:
        if not isinstance(step, dict) or step.get("mode") != "observe" or not step.get("ok"):
            continue
        action = step.get("action")
        if not isinstance(action, dict) or action.get("tool") != SEND_MESSAGE:
            continue
        entry = by_index.get(step.get("log_index"))
        result = entry.get("result") if isinstance(entry, dict) else None
        proposal_id = result.get("proposal_id") if isinstance(result, dict) else None
        if not isinstance(proposal_id, str):
            continue
        args = entry.get("args") if isinstance(entry, dict) else None
        status = answered.get(proposal_id, "expired" if proposal_id in expired else "pending")
        proposals.append(
            {
                "proposal_id": proposal_id,
                "turn": step.get("turn"),
                "content": str(args.get("content", "")) if isinstance(args, dict) else "",
                "status": status,
                "expired_at": None,
            }
        )
    return proposals
