"""People's verdicts on a run beside the simulator's and the judge's: ``annotations.jsonl`` in its folder.

A person marks each proposal of an episode ``accept`` or ``reject`` (what they would have answered in the
user's seat) and each text a judge read ``pass`` or ``fail`` (whether it meets the check's criterion). Each
mark is one line, appended and never rewritten, with who made it and when (wall-clock time: this is a
person's work, not the simulation). A person who changes their mind marks the item again: the last line of
theirs for an item is their verdict (:func:`latest_annotations`).

Items are named within their episode: a proposal by its id (``proposal-1``), a judged text by its goal, its
check's index and the log entries the judge read (``practice_told:0:7``, entries joined by ``+``).
"""

from __future__ import annotations

import os
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Literal

from pydantic import BaseModel, ConfigDict, Field, ValidationError, model_validator

from pare.errors import UserInputError
from pare.results.trajectory import Trajectory
from pare.scenarios.checks import JUDGE_SAID

ANNOTATIONS = "annotations.jsonl"
ItemKind = Literal["proposal", "judged"]
Label = Literal["accept", "reject", "pass", "fail"]
LABELS: Mapping[str, tuple[Label, Label]] = {"proposal": ("accept", "reject"), "judged": ("pass", "fail")}
"""The two verdicts a person gives each kind of item: the first is the positive one."""
MAX_ANNOTATOR = 80


class Annotation(BaseModel):
    """One person's verdict on one item of one episode."""

    model_config = ConfigDict(extra="forbid", frozen=True)

    scenario_id: str = Field(min_length=1, max_length=200)
    run: int = Field(ge=1)
    kind: ItemKind
    item: str = Field(min_length=1, max_length=200, description="The proposal's id, or goal:check:entries.")
    label: Label
    annotator: str = Field(min_length=1, max_length=MAX_ANNOTATOR, description="Who marked it.")
    at: str = Field(description="When, as an ISO 8601 wall-clock time in UTC.")

    @model_validator(mode="after")
    def _label_fits_kind(self) -> Annotation:
        if self.label not in LABELS[self.kind]:
            raise ValueError(f"a {self.kind} is marked {' or '.join(LABELS[self.kind])}, not {self.label!r}")
        return self

    @property
    def key(self) -> tuple[str, str, int, str, str]:
        """Who judged which item: (annotator, scenario, run, kind, item)."""
        return (self.annotator, self.scenario_id, self.run, self.kind, self.item)

    @property
    def positive(self) -> bool:
        """Whether the person accepted the proposal or passed the text."""
        return self.label == LABELS[self.kind][0]


def append_annotation(folder: Path, annotation: Annotation) -> None:
    """Append ``annotation`` to the run folder's annotations as one line, in one write (an append of a
    few hundred bytes is never interleaved with another's).
    """
    line = (annotation.model_dump_json() + "\n").encode("utf-8")
    handle = os.open(folder / ANNOTATIONS, os.O_WRONLY | os.O_CREAT | os.O_APPEND, 0o644)
    try:
        os.write(handle, line)
    finally:
        os.close(handle)


def read_annotations(folder: Path) -> list[Annotation]:
    """Every annotation of the run folder, in the order they were made (none when it has no file).

    Raises:
        UserInputError: A line is not an annotation (named by file and line).
    """
    file = folder / ANNOTATIONS
    if not file.exists():
        return []
    found: list[Annotation] = []
    with file.open(encoding="utf-8") as lines:
        for number, line in enumerate(lines, 1):
            if not line.strip():
                continue
            try:
                found.append(Annotation.model_validate_json(line))
            except ValidationError as error:
                problem = error.errors()[0]
                where = ".".join(str(part) for part in problem["loc"]) or "the line"
                raise UserInputError(
                    f"{file}:{number}: not an annotation ({where}: {problem['msg']})"
                ) from None
    return found


def latest_annotations(annotations: Iterable[Annotation]) -> list[Annotation]:
    """Each person's last verdict on each item, in the order of the items' first marks."""
    latest: dict[tuple[str, str, int, str, str], Annotation] = {}
    for annotation in annotations:
        latest[annotation.key] = annotation
    return list(latest.values())


@dataclass(frozen=True)
class JudgedItem:
    """One text a judge read for a check, and what the judge said."""

    item: str
    goal: str
    check: int
    criterion: str
    entries: tuple[int, ...]
    passed: bool
    reason: str


def judged_items(trajectory: Trajectory | None) -> list[JudgedItem]:
    """Every text a judge model read in an episode, from its trajectory (a check's ``judged`` texts, each
    with its verdict); none without a trajectory.
    """
    found: list[JudgedItem] = []
    for goal in trajectory.outcome.goals if trajectory is not None else ():
        for check in goal.checks:
            for judged in check.judged:
                entries = tuple(judged.entries)
                found.append(
                    JudgedItem(
                        item=judged_item_id(goal.id, check.index, entries),
                        goal=goal.id,
                        check=check.index,
                        criterion=_criterion(check.detail),
                        entries=entries,
                        passed=judged.verdict.passed,
                        reason=judged.verdict.reason,
                    )
                )
    return found


def judged_item_id(goal: str, check: int, entries: Sequence[int]) -> str:
    """The name of a judged text within its episode: ``goal:check:entries``."""
    return f"{goal}:{check}:{'+'.join(str(index) for index in entries)}"


def _criterion(detail: str) -> str:
    """The criterion a judge check's detail names (``... for: CRITERION``, before the judge's reasons)."""
    return detail.split(JUDGE_SAID, 1)[0].split(" for: ", 1)[-1].strip()
