"""The human's word on generated candidates: list those waiting in a folder, move accepted ones into a
library folder and rejected ones aside with the reason, and log every decision.
"""

from __future__ import annotations

import json
import os
from dataclasses import dataclass
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

from pare.errors import UserInputError, did_you_mean
from pare.generate.folder import read_provenance
from pare.output_paths import make_output_folder
from pare.scenarios.loader import load_scenario
from pare.scenarios.model import Scenario
from pare.scenarios.schema import SCHEMA_FILE
from pare.yaml_source import read_text_file

REJECTED = "rejected"
REVIEWS = "reviews.jsonl"
_SCHEMA_LINE = "# yaml-language-server: $schema="


@dataclass(frozen=True, slots=True)
class PendingCandidate:
    """A candidate file waiting for review: its scenario (``None`` with ``error`` when it no longer
    loads) and its provenance header.
    """

    path: Path
    scenario: Scenario | None
    error: str | None
    provenance: dict[str, Any] | None

    @property
    def scenario_id(self) -> str:
        """The candidate's id (its file name)."""
        return self.path.stem


def pending(folder: Path) -> list[PendingCandidate]:
    """The candidates waiting in ``folder`` (its top-level ``*.yaml`` files), by id."""
    if not folder.is_dir():
        raise UserInputError(f"{folder}: no such folder of generated candidates")
    found = []
    for path in sorted(folder.glob("*.yaml")):
        try:
            text = _read(path)
        except UserInputError as problem:  # a FIFO, a device or bytes that are not text: listed, never read
            found.append(PendingCandidate(path, None, str(problem), None))
            continue
        try:
            scenario, error = load_scenario(path), None
        except UserInputError as problem:
            scenario, error = None, str(problem)
        found.append(PendingCandidate(path, scenario, error, read_provenance(text)))
    return found


def _read(path: Path) -> str:
    """A candidate's text, read only when it is a regular UTF-8 file of at most the size a scenario may be."""
    try:
        return read_text_file(path)
    except OSError as error:  # UnreadableFile says why; a missing file is an OSError too
        reason = str(error).removeprefix("cannot read it: ")
        raise UserInputError(f"{path}: cannot read the candidate: {reason}") from None


def _find(folder: Path, scenario_id: str) -> Path:
    path = folder / f"{scenario_id}.yaml"
    if not os.path.lexists(path):  # anything there is found; reading it says what is wrong with it
        waiting = [p.stem for p in folder.glob("*.yaml")]
        raise UserInputError(
            f"no candidate '{scenario_id}' waiting in {folder}.{did_you_mean(scenario_id, waiting)}"
            + (f" Waiting: {', '.join(sorted(waiting))}" if waiting else " None is waiting.")
        )
    return path


def accept(folder: Path, scenario_id: str, library: Path, *, note: str = "") -> Path:
    """Move candidate ``scenario_id`` into the ``library`` folder (its schema line made relative to the
    library's schema); return the new path. A candidate that no longer loads, or whose id the library
    already has, is refused.
    """
    source = _find(folder, scenario_id)
    load_scenario(source)  # a broken file never enters a library
    make_output_folder(library, "the library folder")
    target = library / source.name
    if target.exists():
        raise UserInputError(f"{target} exists: the library already has a scenario '{scenario_id}'")
    schema = Path(os.path.relpath(SCHEMA_FILE.resolve(), library.resolve())).as_posix()
    lines = _read(source).splitlines(keepends=True)
    lines = [f"{_SCHEMA_LINE}{schema}\n" if line.startswith(_SCHEMA_LINE) else line for line in lines]
    target.write_text("".join(lines), encoding="utf-8")
    source.unlink()
    _log(folder, scenario_id, "accepted", note, target)
    return target


def reject(folder: Path, scenario_id: str, reason: str) -> Path:
    """Move candidate ``scenario_id`` to ``folder/rejected/`` with ``reason`` written at its top."""
    if not reason.strip():
        raise UserInputError("a rejection needs a reason (--reason)")
    source = _find(folder, scenario_id)
    target = folder / REJECTED / source.name
    reason_line = "# rejected: " + " ".join(reason.split()) + "\n"
    text = _read(source)
    target.parent.mkdir(exist_ok=True)
    target.write_text(reason_line + text, encoding="utf-8")
    source.unlink()
    _log(folder, scenario_id, "rejected", reason, target)
    return target


def _log(folder: Path, scenario_id: str, decision: str, reason: str, target: Path) -> None:
    entry = {
        "scenario_id": scenario_id,
        "decision": decision,
        "reason": reason,
        "moved_to": str(target),
        "at": datetime.now(UTC).strftime("%Y-%m-%dT%H:%M:%SZ"),
    }
    with (folder / REVIEWS).open("a", encoding="utf-8") as handle:
        handle.write(json.dumps(entry, ensure_ascii=False) + "\n")
