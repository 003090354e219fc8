"""Reading a run folder: the manifest, the episode records and where each trajectory lives.

The layout is described in :mod:`pare.bench.store`, the folder's writer. Everything here only reads, so
reports, the viewer and re-grading can use it without the package that runs models; lines are only ever
appended, so a run may be read while it is still being written.
"""

from __future__ import annotations

import hashlib
import json
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from pydantic import ValidationError

from pare.errors import UserInputError
from pare.results.records import EpisodeRecord
from pare.scenarios.model import Scenario
from pare.yaml_source import UnreadableFile, read_text_file

MANIFEST = "manifest.json"
EPISODES = "episodes.jsonl"
TRAJECTORIES = "trajectories"
SWEEP_FILE = "sweep.json"
MANIFEST_FORMAT = 1
MAX_EPISODES_BYTES = 2 * 1024**3
"""The largest episodes file read (a record is a few KB: a million episodes fit)."""
MAX_MANIFEST_BYTES = 64 * 1024 * 1024
"""The largest manifest or sweep description read (a 10,000-scenario run's manifest is about 1 MB)."""
MAX_RUNS = 1_000
"""The most runs per scenario (the paper's protocol uses 4)."""

EpisodeKey = tuple[str, int]


def scenario_hash(scenario: Scenario) -> str:
    """A content hash of a scenario: the same data gives the same hash, whatever the file's layout."""
    return scenario.content_hash()


def scenario_set_hash(hashes: Mapping[str, str]) -> str:
    """A content hash of a set of scenarios (ids and their hashes)."""
    text = "\n".join(f"{scenario_id}:{hashes[scenario_id]}" for scenario_id in sorted(hashes))
    return hashlib.sha256(text.encode("utf-8")).hexdigest()[:16]


def trajectory_path(scenario_id: str, run: int) -> str:
    """Where one episode's trajectory lives, relative to the run folder."""
    return f"{TRAJECTORIES}/{scenario_id}/run-{run}.json"


def read_run_file(file: Path, what: str, *, max_bytes: int) -> str:
    """The UTF-8 text of one file of a run folder, read only when it is a regular file of at most
    ``max_bytes`` (a FIFO would hang the reader, ``/dev/zero`` fill its memory).

    Raises:
        UserInputError: It is missing, not a regular file, too large or not UTF-8 (``what`` names it).
    """
    try:
        return read_text_file(file, max_bytes=max_bytes)
    except UnreadableFile as error:
        reason = str(error).removeprefix("cannot read it: ")
        raise UserInputError(f"{file}: cannot read {what}: {reason}") from None
    except OSError as error:  # missing, or refused by the system
        raise UserInputError(f"{file}: cannot read {what}: {error.strerror or error}") from None


def read_records(path: Path) -> list[EpisodeRecord]:
    """Every well-formed line of an episodes file, in order; an unfinished last line is ignored."""
    if not path.exists():
        return []
    records: list[EpisodeRecord] = []
    lines = read_run_file(path, "the episodes file", max_bytes=MAX_EPISODES_BYTES).split("\n")
    for number, line in enumerate(lines, start=1):
        if not line.strip():
            continue
        try:
            records.append(EpisodeRecord.model_validate_json(line))
        except ValidationError as error:
            if number == len(lines):  # the tail of a write cut short by a kill
                break
            raise UserInputError(
                f"{path}:{number}: not an episode record: {error.errors()[0]['msg']}"
            ) from None
    return records


def read_manifest(file: Path) -> dict[str, Any]:
    """A run folder's manifest, or a :class:`UserInputError` that says what is wrong with it."""
    text = read_run_file(file, "the manifest", max_bytes=MAX_MANIFEST_BYTES)
    try:
        data = json.loads(text)
    except json.JSONDecodeError as error:
        raise UserInputError(f"{file}: cannot read the manifest: {error}") from None
    if not isinstance(data, dict) or not isinstance(data.get("format"), int):
        raise UserInputError(f"{file}: not a PARE run manifest (a JSON object with a format number)")
    if data["format"] != MANIFEST_FORMAT:
        raise UserInputError(
            f"{file}: manifest format {data['format']}, but this PARE reads format {MANIFEST_FORMAT}; "
            "read it with the PARE version that wrote it"
        )
    return data


def latest_records(records: Iterable[EpisodeRecord]) -> dict[EpisodeKey, EpisodeRecord]:
    """One record per episode: the first complete one, else the last failed one."""
    chosen: dict[EpisodeKey, EpisodeRecord] = {}
    for record in records:
        current = chosen.get(record.key)
        if current is None or (not current.complete):
            chosen[record.key] = record
    return chosen


@dataclass(frozen=True)
class LoadedRun:
    """One configuration's results as reports see them."""

    path: Path
    label: str
    manifest: dict[str, Any]
    runs: int
    planned: list[EpisodeKey]
    records: list[EpisodeRecord]
    sweep_point: dict[str, Any]


MAX_PLANNED_EPISODES = 1_000_000
"""The most episodes a run folder's plan may list for reports (a thousand scenarios of a thousand runs)."""


def load_run(path: Path) -> LoadedRun:
    """Read one run folder (no lock needed: lines are only ever appended)."""
    file = path / MANIFEST
    if not file.exists():
        raise UserInputError(
            f"{path} is not a PARE run folder (no {MANIFEST}); pass the folder 'pare run' made"
        )
    manifest = read_manifest(file)
    plan = manifest.get("plan", {})
    runs = plan.get("runs", 1) if isinstance(plan, dict) else None
    scenarios = plan.get("scenarios", {}) if isinstance(plan, dict) else None
    if (
        not isinstance(runs, int)
        or isinstance(runs, bool)
        or runs < 1
        or not isinstance(scenarios, dict | list)
    ):
        raise UserInputError(
            f"{file}: its 'plan' is not a run plan (runs and scenarios); the file is damaged"
        )
    # Every planned episode is listed (the missing ones are reported): a damaged plan would fill the memory.
    if runs > MAX_RUNS:
        raise UserInputError(
            f"{file}: its plan has {runs} runs per scenario, more than a run can have ({MAX_RUNS}); "
            "the file is damaged"
        )
    if len(scenarios) * runs > MAX_PLANNED_EPISODES:
        raise UserInputError(
            f"{file}: its plan has {len(scenarios)} scenarios x {runs} runs, more than the "
            f"{MAX_PLANNED_EPISODES:,} episodes a report reads; the file is damaged"
        )
    planned = [(str(scenario_id), run) for scenario_id in sorted(scenarios) for run in range(1, runs + 1)]
    sweep_point = manifest.get("sweep_point", {})
    if not isinstance(sweep_point, dict):
        raise UserInputError(f"{file}: its 'sweep_point' is not a mapping; the file is damaged")
    records = latest_records(read_records(path / EPISODES))
    return LoadedRun(
        path=path,
        label=str(manifest.get("label", path.name)),
        manifest=manifest,
        runs=runs,
        planned=planned,
        records=[records[key] for key in sorted(records)],
        sweep_point=dict(sweep_point),
    )


def run_folders(paths: Iterable[Path]) -> list[Path]:
    """The run folders named by ``paths``: a run folder itself, or every run inside a sweep folder."""
    found: list[Path] = []
    for path in paths:
        if (path / MANIFEST).exists():
            found.append(path)
            continue
        if not path.is_dir():
            raise UserInputError(f"{path}: no such run folder")
        inner = sorted(child for child in path.iterdir() if (child / MANIFEST).exists())
        if (path / SWEEP_FILE).exists():  # a sweep lists its points in the grid's order
            order = _sweep_order(path / SWEEP_FILE)
            inner.sort(key=lambda child: order.index(child.name) if child.name in order else len(order))
        if not inner:
            raise UserInputError(
                f"{path} holds no PARE run ({MANIFEST} missing); pass a folder 'pare run' made"
            )
        found.extend(inner)
    return found


def _sweep_order(file: Path) -> list[str]:
    """The point folders a sweep description lists, in the grid's order."""
    text = read_run_file(file, "the sweep description", max_bytes=MAX_MANIFEST_BYTES)
    try:
        points = json.loads(text)["points"]
        return [str(point["folder"]) for point in points]
    except (ValueError, KeyError, TypeError) as error:
        raise UserInputError(
            f"{file}: not a PARE sweep description ({error!s}); the file is damaged"
        ) from None
