"""What a user calibration leaves, read without running anything: its cases' decisions and their measures.

A calibration folder (``pare calibrate``) holds ``calibration.json`` (what was calibrated: the user's
policy and model, its persona of trust, the protocol, provenance), ``decisions.jsonl`` (one line per
finished case, the commit point), a trajectory per case and the model-call cache. The measures: the
confusion table of the answer that was right against the decision, the rate of accepting when the proposal
was wrong and of rejecting when it was right (with Wilson 95% intervals), how often the user looked things
up before answering and what it decided then, and the share decided rightly per case kind, app and tag.
"""

from __future__ import annotations

import json
import math
from collections.abc import Callable, Iterable, Sequence
from pathlib import Path
from statistics import NormalDist
from typing import Any, Literal

from pydantic import BaseModel, ConfigDict, Field, ValidationError

from pare.errors import UserInputError
from pare.results.run_folder import MAX_EPISODES_BYTES, MAX_MANIFEST_BYTES, read_run_file

CALIBRATION_MANIFEST = "calibration.json"
DECISIONS_FILE = "decisions.jsonl"
CALIBRATION_FORMAT = 1

Decision = Literal["accept", "reject", "no_answer", "not_reached"]
"""What the user did with a case's proposal: answered it, let it go unanswered (it was withdrawn, or the
user's actions ran out), or never saw it (the oracle did not reach the moment: a broken case)."""
DECISIONS: tuple[Decision, ...] = ("accept", "reject", "no_answer", "not_reached")
Expected = Literal["accept", "reject"]


class CaseRecord(BaseModel):
    """One finished (or failed) case, as ``decisions.jsonl`` keeps it."""

    model_config = ConfigDict(extra="forbid", frozen=True)

    case_id: str
    case_hash: str = Field(description="A hash of what the case plays; a changed case is played again.")
    scenario_id: str
    kind: str = Field(description="oracle, variant, mutant, unrelated or tempting.")
    name: str
    expected: Expected
    proposal: str
    what: str = ""
    apps: list[str] = Field(default_factory=list)
    tags: list[str] = Field(default_factory=list)
    status: Literal["complete", "failed"]
    decision: Decision | None = None
    looked: int = Field(default=0, description="Actions taken before answering: looking things up.")
    reason: str = ""
    trajectory: str | None = None
    usage: dict[str, Any] = Field(default_factory=dict)
    failure: str | None = None

    @property
    def reached(self) -> bool:
        """Whether the user was put the proposal (the case is complete and its moment came)."""
        return self.status == "complete" and self.decision not in (None, "not_reached")


class Rate(BaseModel):
    """A proportion with its Wilson score interval."""

    model_config = ConfigDict(frozen=True)

    hits: int
    total: int
    value: float | None
    low: float | None
    high: float | None


def wilson(hits: int, total: int, confidence: float = 0.95) -> Rate:
    """``hits`` out of ``total`` with its Wilson score interval (``None`` values when ``total`` is 0).

    The Wilson interval stays inside [0, 1] and keeps its coverage for small counts and rates near 0 or 1,
    which is where a well-calibrated user's error rates are.
    """
    if total == 0:
        return Rate(hits=0, total=0, value=None, low=None, high=None)
    z = NormalDist().inv_cdf(0.5 + confidence / 2)
    p = hits / total
    centre = (p + z * z / (2 * total)) / (1 + z * z / total)
    spread = z * math.sqrt(p * (1 - p) / total + z * z / (4 * total * total)) / (1 + z * z / total)
    low = 0.0 if hits == 0 else max(0.0, min(p, centre - spread))  # exact at the ends, not 1e-17 off
    high = 1.0 if hits == total else min(1.0, max(p, centre + spread))
    return Rate(hits=hits, total=total, value=p, low=low, high=high)


class GroupRow(BaseModel):
    """The measures of one group of cases (a case kind, an app, a tag)."""

    model_config = ConfigDict(frozen=True)

    group: str
    cases: int
    right: Rate
    """Decided as expected."""
    accepted: Rate
    """Accepted, whatever the right answer."""
    accept_when_wrong: Rate
    reject_when_right: Rate


class CalibrationMetrics(BaseModel):
    """The measures of one calibrated user."""

    model_config = ConfigDict(frozen=True)

    label: str
    user_trust: str
    protocol: str
    confusion: dict[str, dict[str, int]]
    """Expected answer -> decision -> cases."""
    accept_when_wrong: Rate
    """Accepted, of the cases whose proposal was wrong (an unanswered one is not accepted)."""
    reject_when_right: Rate
    """Rejected, of the cases whose proposal was right (an unanswered one is not rejected)."""
    no_answer: Rate
    looked: Rate
    """Cases in which the user looked something up before answering."""
    after_looking: dict[str, int]
    """What the user decided after looking something up."""
    mean_looked: float | None
    by_kind: list[GroupRow]
    by_app: list[GroupRow]
    by_tag: list[GroupRow]
    planned: int
    complete: int
    failed: int
    not_reached: int
    cost_usd: float


class LoadedCalibration(BaseModel):
    """A calibration folder as read."""

    model_config = ConfigDict(frozen=True)

    path: str
    manifest: dict[str, Any]
    records: list[CaseRecord]

    @property
    def label(self) -> str:
        """Who was calibrated, as the manifest names it."""
        return str(self.manifest.get("label", Path(self.path).name))


def is_calibration(path: Path) -> bool:
    """Whether ``path`` is a calibration folder."""
    return (path / CALIBRATION_MANIFEST).is_file()


def read_records(file: Path) -> list[CaseRecord]:
    """The records of ``decisions.jsonl``, the last one of each case winning (a case played again after it
    changed); a torn last line (a killed writer) is skipped.
    """
    if not file.exists():
        return []
    found: dict[str, CaseRecord] = {}
    lines = read_run_file(file, "the decisions", max_bytes=MAX_EPISODES_BYTES).splitlines()
    for number, line in enumerate(lines, 1):
        if not line.strip():
            continue
        try:
            record = CaseRecord.model_validate_json(line)
        except ValidationError as error:
            if number == len(lines):
                continue
            raise UserInputError(f"{file}, line {number}: not a calibration record: {error}") from None
        found[record.case_id] = record
    return list(found.values())


def load_calibration(path: Path) -> LoadedCalibration:
    """Read a calibration folder.

    Raises:
        UserInputError: ``path`` is not a calibration folder, or a file in it is not what it should be.
    """
    file = path / CALIBRATION_MANIFEST
    if not file.is_file():
        raise UserInputError(
            f"{path} is not a calibration folder (no {CALIBRATION_MANIFEST}); pass the folder "
            "'pare calibrate' made"
        )
    try:
        manifest = json.loads(read_run_file(file, "the calibration manifest", max_bytes=MAX_MANIFEST_BYTES))
    except json.JSONDecodeError as error:
        raise UserInputError(f"{file}: not valid JSON ({error})") from None
    if not isinstance(manifest, dict) or manifest.get("format") != CALIBRATION_FORMAT:
        raise UserInputError(f"{file}: not a calibration manifest of format {CALIBRATION_FORMAT}")
    return LoadedCalibration(path=str(path), manifest=manifest, records=read_records(path / DECISIONS_FILE))


def _group_rows(records: Sequence[CaseRecord], keys: Callable[[CaseRecord], Iterable[str]]) -> list[GroupRow]:
    groups: dict[str, list[CaseRecord]] = {}
    for record in records:
        for key in keys(record):
            groups.setdefault(key, []).append(record)
    return [_row(name, members) for name, members in sorted(groups.items())]


def _row(name: str, records: Sequence[CaseRecord]) -> GroupRow:
    wrong = [r for r in records if r.expected == "reject"]
    right = [r for r in records if r.expected == "accept"]
    return GroupRow(
        group=name,
        cases=len(records),
        right=wilson(sum(r.decision == r.expected for r in records), len(records)),
        accepted=wilson(sum(r.decision == "accept" for r in records), len(records)),
        accept_when_wrong=wilson(sum(r.decision == "accept" for r in wrong), len(wrong)),
        reject_when_right=wilson(sum(r.decision == "reject" for r in right), len(right)),
    )


def calibration_metrics(loaded: LoadedCalibration) -> CalibrationMetrics:
    """The measures of a calibration folder's reached cases (see the module's docstring)."""
    records = loaded.records
    reached = [r for r in records if r.reached]
    confusion = {
        expected: {decision: 0 for decision in ("accept", "reject", "no_answer")}
        for expected in ("accept", "reject")
    }
    for record in reached:
        confusion[record.expected][str(record.decision)] += 1
    looked = [r for r in reached if r.looked > 0]
    after: dict[str, int] = {"accept": 0, "reject": 0, "no_answer": 0}
    for record in looked:
        after[str(record.decision)] += 1
    row = _row("all", reached)
    protocol = loaded.manifest.get("protocol", {})
    settings = protocol.get("settings", {}) if isinstance(protocol, dict) else {}
    planned = loaded.manifest.get("cases_planned")
    return CalibrationMetrics(
        label=loaded.label,
        user_trust=str(settings.get("user_trust", "demanding")),
        protocol=str(protocol.get("preset", "pare")) if isinstance(protocol, dict) else "pare",
        confusion=confusion,
        accept_when_wrong=row.accept_when_wrong,
        reject_when_right=row.reject_when_right,
        no_answer=wilson(sum(r.decision == "no_answer" for r in reached), len(reached)),
        looked=wilson(len(looked), len(reached)),
        after_looking=after,
        mean_looked=(sum(r.looked for r in reached) / len(reached)) if reached else None,
        by_kind=_group_rows(reached, lambda r: [r.kind]),
        by_app=_group_rows(reached, lambda r: r.apps),
        by_tag=_group_rows(reached, lambda r: r.tags),
        planned=planned if isinstance(planned, int) else len(records),
        complete=sum(r.status == "complete" for r in records),
        failed=sum(r.status == "failed" for r in records),
        not_reached=sum(r.status == "complete" and r.decision == "not_reached" for r in records),
        cost_usd=round(sum(float(r.usage.get("known_cost_usd") or 0.0) for r in records), 6),
    )
