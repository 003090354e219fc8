"""A run's folder: the manifest, one append-only line per finished episode, one trajectory per episode.

Layout::

    RUN/manifest.json                    provenance and the plan (rewritten at the start of each session)
    RUN/episodes.jsonl                   one EpisodeRecord per line, appended as each episode finishes
    RUN/trajectories/<scenario>/run-<r>.json   the full trajectory of a complete episode
    RUN/model_calls.sqlite               the record/replay cache of model calls (when enabled)

The episode line is the commit point: a trajectory is written (atomically) before its line, so a line
always names a trajectory that exists, and an episode whose line was never written is simply run again
on resume. A line cut short by a kill is dropped when the store is next opened. Only one process may
write a run at a time (an advisory lock on ``RUN/.lock``).
"""

from __future__ import annotations

import hashlib
import json
import os
import platform
import sys
import time
from collections.abc import Iterable, Iterator, Mapping
from dataclasses import dataclass, field
from datetime import UTC, datetime
from importlib import metadata
from pathlib import Path
from typing import IO, Any

from pydantic import ValidationError

from pare import __version__
from pare.agents.models.secrets import redact_secrets
from pare.bench.records import EpisodeRecord
from pare.bench.runconfig import RunConfig
from pare.errors import UserInputError
from pare.scenarios.model import Scenario

try:  # advisory locks exist on POSIX; elsewhere a run simply is not protected against a second writer
    import fcntl
except ImportError:  # pragma: no cover - Windows
    fcntl = None  # type: ignore[assignment]

MANIFEST = "manifest.json"
EPISODES = "episodes.jsonl"
TRAJECTORIES = "trajectories"
CACHE_FILE = "model_calls.sqlite"
LOCK = ".lock"
SWEEP_FILE = "sweep.json"
SYNC_INTERVAL_S = 1.0
"""At most this long between forcing the episodes file to the disk (it is handed to the OS at once)."""
MANIFEST_FORMAT = 1

PROVENANCE_PACKAGES = ("pydantic", "openai", "litellm", "ray", "jinja2", "rich", "typer")

EpisodeKey = tuple[str, int]


def scenario_hash(scenario: Scenario) -> str:
    """A content hash of a scenario: the same data gives the same hash, whatever the file's layout."""
    data = json.dumps(scenario.model_dump(mode="json"), sort_keys=True, separators=(",", ":"))
    return hashlib.sha256(data.encode("utf-8")).hexdigest()[:16]


def scenario_set_hash(hashes: Mapping[str, str]) -> str:
    """A content hash of a set of scenarios (ids and their hashes)."""
    text = "\n".join(f"{scenario_id}:{hashes[scenario_id]}" for scenario_id in sorted(hashes))
    return hashlib.sha256(text.encode("utf-8")).hexdigest()[:16]


def provenance() -> dict[str, Any]:
    """Versions of PARE, Python and the libraries that shape a run."""
    versions: dict[str, str | None] = {}
    for package in PROVENANCE_PACKAGES:
        try:
            versions[package] = metadata.version(package)
        except metadata.PackageNotFoundError:
            versions[package] = None
    return {
        "pare": __version__,
        "python": sys.version.split()[0],
        "implementation": platform.python_implementation(),
        "platform": platform.platform(terse=True),
        "packages": versions,
    }


def trajectory_path(scenario_id: str, run: int) -> str:
    """Where one episode's trajectory lives, relative to the run folder."""
    return f"{TRAJECTORIES}/{scenario_id}/run-{run}.json"


_MADE_FOLDERS: set[Path] = set()
"""Folders this process has made or found, so writing the next trajectory beside them skips mkdir."""


def _write_atomically(path: Path, text: str) -> None:
    if path.parent not in _MADE_FOLDERS:
        path.parent.mkdir(parents=True, exist_ok=True)
        _MADE_FOLDERS.add(path.parent)
    temporary = path.with_name(path.name + ".tmp")
    try:
        temporary.write_text(text, encoding="utf-8")
    except FileNotFoundError:  # the folder went away since (a run folder deleted and made again)
        path.parent.mkdir(parents=True, exist_ok=True)
        temporary.write_text(text, encoding="utf-8")
    os.replace(temporary, path)


def read_records(path: Path) -> list[EpisodeRecord]:
    """Every well-formed line of an episodes file, in order; an unfinished last line is ignored."""
    if not path.exists():
        return []
    records: list[EpisodeRecord] = []
    try:
        lines = path.read_bytes().decode("utf-8").split("\n")
    except UnicodeDecodeError as error:
        raise UserInputError(f"{path}: not an episodes file (not UTF-8 text at byte {error.start})") from None
    except OSError as error:
        raise UserInputError(f"{path}: cannot read the episodes file: {error.strerror or error}") from None
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
    try:
        data = json.loads(file.read_bytes().decode("utf-8"))
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as error:
        reason = error.strerror if isinstance(error, OSError) and error.strerror else error
        raise UserInputError(f"{file}: cannot read the manifest: {reason}") from None
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


@dataclass
class RunStore:
    """The writer of one run folder, for one session of ``pare run``."""

    path: Path
    manifest: dict[str, Any]
    records: dict[EpisodeKey, EpisodeRecord] = field(default_factory=dict)
    hashes: dict[str, str] = field(default_factory=dict)
    """The content hash of every scenario of the run, by id (computed once, when the store is opened)."""
    _lock: IO[str] | None = None
    _episodes: IO[str] | None = None
    _synced_at: float = float("-inf")
    """When the episodes file was last forced to the disk (monotonic seconds)."""

    # -- opening -------------------------------------------------------------------------------------------
    @classmethod
    def open(
        cls,
        path: Path,
        config: RunConfig,
        scenarios: Mapping[str, Scenario],
        *,
        sweep_point: Mapping[str, Any] | None = None,
    ) -> RunStore:
        """Open (or create) the run folder for ``config`` over ``scenarios``, ready to append.

        Refuses a folder made by a different configuration, or whose finished episodes ran a scenario
        that has changed since.
        """
        path.mkdir(parents=True, exist_ok=True)
        lock = _acquire_lock(path)
        try:
            store = cls(path=path, manifest={}, _lock=lock)
            previous = store._read_manifest()
            hashes = {scenario_id: scenario_hash(s) for scenario_id, s in sorted(scenarios.items())}
            store.hashes = hashes
            if previous is not None:
                _check_same_configuration(path, previous, config)
            _repair_tail(path / EPISODES)
            store.records = latest_records(read_records(path / EPISODES))
            _check_scenarios_unchanged(path, store.records, hashes)
            store.manifest = _manifest(config, hashes, previous, sweep_point)
            _write_atomically(
                path / MANIFEST, json.dumps(store.manifest, indent=2, ensure_ascii=False) + "\n"
            )
            store._episodes = (path / EPISODES).open("a", encoding="utf-8")
        except BaseException:
            lock.close()
            raise
        return store

    def _read_manifest(self) -> dict[str, Any] | None:
        file = self.path / MANIFEST
        if not file.exists():
            if (self.path / EPISODES).exists():
                raise UserInputError(
                    f"{self.path} has episode records but no {MANIFEST}; it is not a PARE run"
                )
            strangers = sorted(p.name for p in self.path.iterdir() if p.name not in (LOCK, CACHE_FILE))
            if strangers:
                raise UserInputError(
                    f"{self.path} is not a PARE run folder and is not empty ({', '.join(strangers[:3])}); "
                    "choose another --output"
                )
            return None
        return read_manifest(file)

    # -- writing -------------------------------------------------------------------------------------------
    def done(self, key: EpisodeKey) -> bool:
        """Whether the episode already has a complete record."""
        record = self.records.get(key)
        return record is not None and record.complete

    def append(self, record: EpisodeRecord, trajectory: str | None = None) -> None:
        """Store one finished episode: its trajectory (JSON text) first, then its line (the commit point)."""
        if self._episodes is None:
            raise RuntimeError("the run store is closed")
        if trajectory is not None and record.trajectory is not None:
            _write_atomically(self.path / record.trajectory, trajectory + "\n")
        self._episodes.write(record.model_dump_json() + "\n")
        # Handed to the OS at once: a killed process (kill -9, Ctrl-C) loses nothing it recorded. Forcing
        # it to the disk costs milliseconds, so that is done at most once per SYNC_INTERVAL_S and when the
        # run ends: a power cut loses at most that window, which a resume plays again.
        self._episodes.flush()
        now = time.monotonic()
        if now - self._synced_at >= SYNC_INTERVAL_S:
            os.fsync(self._episodes.fileno())
            self._synced_at = now
        current = self.records.get(record.key)
        if current is None or not current.complete:
            self.records[record.key] = record

    def close(self) -> None:
        """Force what was recorded to the disk and release the folder."""
        if self._episodes is not None:
            self._episodes.flush()
            os.fsync(self._episodes.fileno())
            self._episodes.close()
            self._episodes = None
        if self._lock is not None:
            self._lock.close()
            self._lock = None

    def __enter__(self) -> RunStore:
        return self

    def __exit__(self, *exc_info: object) -> None:
        self.close()


def _acquire_lock(path: Path) -> IO[str]:
    handle = (path / LOCK).open("a", encoding="utf-8")
    if fcntl is not None:
        try:
            fcntl.flock(handle.fileno(), fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            handle.close()
            raise UserInputError(
                f"another 'pare run' is writing {path}; wait for it to finish or choose another --output"
            ) from None
    return handle


def _repair_tail(file: Path) -> None:
    """Cut a last line left unfinished by a kill, so the next line starts on its own."""
    if not file.exists():
        return
    with file.open("rb+") as handle:
        data = handle.read()
        if not data or data.endswith(b"\n"):
            return
        handle.truncate(data.rfind(b"\n") + 1)


def _check_same_configuration(path: Path, manifest: Mapping[str, Any], config: RunConfig) -> None:
    before = manifest.get("identity")
    now = config.identity()
    if before == now:
        return
    differences = sorted(_differences(before, now))
    listed = "\n".join(f"  {where}: {old!r} -> {new!r}" for where, old, new in differences[:12])
    raise UserInputError(
        f"{path} holds a run of a different configuration, so resuming it would mix results:\n{listed}\n"
        "Run the original configuration to resume it, or pass another --output (or none, to get a folder "
        "named after this configuration)."
    )


def _differences(old: Any, new: Any, where: str = "") -> Iterator[tuple[str, Any, Any]]:
    if isinstance(old, dict) and isinstance(new, dict):
        for key in sorted(set(old) | set(new)):
            yield from _differences(old.get(key), new.get(key), f"{where}.{key}" if where else key)
    elif old != new:
        yield (where or "(configuration)", old, new)


def _check_scenarios_unchanged(
    path: Path, records: Mapping[EpisodeKey, EpisodeRecord], hashes: Mapping[str, str]
) -> None:
    changed = sorted(
        {
            record.scenario_id
            for record in records.values()
            if record.complete
            and record.scenario_id in hashes
            and hashes[record.scenario_id] != record.scenario_hash
        }
    )
    if changed:
        raise UserInputError(
            f"{path}: these scenarios changed since their episodes were run, so old and new episodes would "
            f"not be comparable: {', '.join(changed)}. Use a new --output for the changed scenario set."
        )


def _manifest(
    config: RunConfig,
    hashes: Mapping[str, str],
    previous: Mapping[str, Any] | None,
    sweep_point: Mapping[str, Any] | None,
) -> dict[str, Any]:
    sessions = list(previous.get("sessions", [])) if previous else []
    sessions.append(
        {
            "started": datetime.now(UTC).isoformat(timespec="seconds"),
            "pare": __version__,
            "scenarios": len(hashes),
            "runs": config.runs,
            "backend": config.backend,
            "concurrency": config.concurrency,
            "cache": config.cache,
        }
    )
    return {
        "format": MANIFEST_FORMAT,
        "label": config.label(),
        "identity_hash": config.identity_hash(),
        "identity": redact_secrets(config.identity()),
        "config": redact_secrets(config.public_dict()),
        "sweep_point": dict(sweep_point or (previous or {}).get("sweep_point", {})),
        "plan": {"runs": config.runs, "scenarios": dict(hashes)},
        "scenario_set_hash": scenario_set_hash(hashes),
        "provenance": provenance(),
        "sessions": sessions,
    }


# -- reading runs for reports ----------------------------------------------------------------------------
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
    if not isinstance(runs, int) or runs < 1 or not isinstance(scenarios, dict | list):
        raise UserInputError(
            f"{file}: its 'plan' is not a run plan (runs and scenarios); the file is damaged"
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
    try:
        points = json.loads(file.read_bytes().decode("utf-8"))["points"]
        return [str(point["folder"]) for point in points]
    except (OSError, UnicodeDecodeError, ValueError, KeyError, TypeError) as error:
        raise UserInputError(
            f"{file}: not a PARE sweep description ({error!s}); the file is damaged"
        ) from None
