"""Annotation in the viewer: what an episode offers to be marked, and storing a person's mark.

An episode page served by ``pare view`` lists the episode's proposals (to mark accept or reject, as the
person would have answered in the user's seat) and the texts a judge model read (to mark pass or fail
against the check's criterion), each with the machine's verdict hidden behind the person's own until they
mark it. A mark is sent to the server, which checks it names an item of an episode of a run it shows and
appends it to that run folder's ``annotations.jsonl`` (:mod:`pare.results.annotations`).
"""

from __future__ import annotations

import getpass
from collections.abc import Sequence
from dataclasses import dataclass, field
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

from pydantic import ValidationError

from pare.errors import UserInputError
from pare.results.annotations import (
    LABELS,
    Annotation,
    append_annotation,
    judged_items,
    latest_annotations,
    read_annotations,
)
from pare.results.records import EpisodeRecord
from pare.results.trajectory import LogRecord, Trajectory
from pare.viewer._runs import Catalog

MAX_BODY_BYTES = 4096
"""The largest annotation request the server reads."""


@dataclass
class AnnotationItem:
    """One thing of an episode a person can mark."""

    kind: str
    item: str
    title: str
    """The proposal, or the criterion the judge read the text for."""
    text: str
    """The judged text (empty for a proposal: the title is the proposal)."""
    machine: str | None
    """The simulator's answer or the judge's verdict, as a label (``None``: the simulator never answered)."""
    labels: tuple[str, str]
    marks: dict[str, str] = field(default_factory=dict)
    """Each person's last mark, by name."""


def annotation_items(
    record: EpisodeRecord, trajectory: Trajectory | None, annotations: Sequence[Annotation]
) -> list[AnnotationItem]:
    """The proposals and judged texts of one episode, with the marks already made on them."""
    answers = {"accepted": "accept", "rejected": "reject"}
    items = [
        AnnotationItem(
            "proposal", p.proposal_id, p.content, "", answers.get(p.resolution), LABELS["proposal"]
        )
        for p in record.proposals
    ]
    log = {entry.index: entry for entry in trajectory.log} if trajectory is not None else {}
    for judged in judged_items(trajectory):
        text = "\n".join(_text_of(log.get(index)) for index in judged.entries)
        verdict = "pass" if judged.passed else "fail"
        items.append(AnnotationItem("judged", judged.item, judged.criterion, text, verdict, LABELS["judged"]))
    by_key = {(item.kind, item.item): item for item in items}
    for mark in latest_annotations(annotations):
        if (mark.scenario_id, mark.run) == record.key and (mark.kind, mark.item) in by_key:
            by_key[(mark.kind, mark.item)].marks[mark.annotator] = mark.label
    return items


def _account_name() -> str:
    """The name of the account running the viewer (``anonymous`` where the system has none to give)."""
    try:
        return getpass.getuser()
    except (KeyError, OSError):  # no USER variable and no entry in the password database (containers)
        return "anonymous"


def _text_of(entry: LogRecord | None) -> str:
    """The texts a logged call carried (its string arguments), as the judge was given them."""
    if entry is None:
        return ""
    return "\n".join(value for value in entry.args.values() if isinstance(value, str))


def record_annotation(catalog: Catalog, body: Any, *, now: datetime | None = None) -> Annotation:
    """Check a mark sent by an episode page and append it to its run folder's annotations.

    ``body`` holds ``configuration`` (the id in URLs), ``scenario_id``, ``run``, ``kind``, ``item``,
    ``label`` and ``annotator`` (empty: the name of the account running the viewer).

    Raises:
        UserInputError: The mark is malformed, or names no item of an episode the viewer shows.
    """
    if not isinstance(body, dict):
        raise UserInputError("an annotation is a JSON object")
    configuration = catalog.get(str(body.get("configuration", "")))
    if configuration is None:
        raise UserInputError(f"no configuration {body.get('configuration')!r} in this viewer")
    annotator = str(body.get("annotator") or "").strip() or _account_name()
    stamp = (now or datetime.now(UTC)).isoformat(timespec="seconds")
    fields = {name: body.get(name) for name in ("scenario_id", "run", "kind", "item", "label")}
    try:
        annotation = Annotation.model_validate({**fields, "annotator": annotator, "at": stamp})
    except ValidationError as error:
        problem = error.errors()[0]
        where = ".".join(str(part) for part in problem["loc"]) or "the annotation"
        raise UserInputError(f"{where}: {problem['msg']}") from None
    record = configuration.records.get((annotation.scenario_id, annotation.run))
    if record is None or not record.complete:
        raise UserInputError(
            f"{configuration.label} has no complete episode {annotation.scenario_id} run {annotation.run}"
        )
    trajectory = configuration.trajectory(record)
    known = {(item.kind, item.item) for item in annotation_items(record, trajectory, [])}
    if (annotation.kind, annotation.item) not in known:
        raise UserInputError(
            f"{annotation.scenario_id} run {annotation.run} has no {annotation.kind} {annotation.item!r}"
        )
    append_annotation(configuration.path, annotation)
    return annotation


def episode_annotations(
    folder: Path, record: EpisodeRecord, trajectory: Trajectory | None
) -> list[AnnotationItem]:
    """The items of an episode with the marks its run ``folder`` holds."""
    return annotation_items(record, trajectory, read_annotations(folder))
