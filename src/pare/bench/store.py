"""A run's folder: the manifest, one append-only line per finished episode, one trajectory per episode.

Layout::

    RUN/manifest.json                    provenance, the plan, what the model requests carry (rewritten
                                         at the start of each session and when a refusal is learned)
    RUN/episodes.jsonl                   one EpisodeRecord per line, appended as each episode finishes
    RUN/trajectories/<scenario>/run-<r>.json   the full trajectory of a complete episode
    RUN/model_calls.sqlite               the record/replay cache of model calls (when enabled)

The episode line is the commit point: a trajectory is written (atomically) before its line, so a line
always names a trajectory that exists, and an episode whose line was never written is simply run again
on resume. A line cut short by a kill is dropped when the store is next opened. Only one process may
write a run at a time (an advisory lock on ``RUN/.lock``).

The files are written by a small process of the store's own (:mod:`pare.bench._store_writer`), so the
next episode plays while the last one is written. Only an episode whose line is written counts as
finished (:meth:`RunStore.committed`): a killed run loses nothing it reported.
"""

from __future__ import annotations

import contextlib
import json
import os
import platform
import select
import subprocess
import sys
import threading
import time
from collections import deque
from collections.abc import Iterator, Mapping
from dataclasses import dataclass, field
from datetime import UTC, datetime
from importlib import metadata
from pathlib import Path
from typing import IO, Any

from pare import __version__
from pare.agents.models.secrets import redact_secrets
from pare.bench import _store_writer
from pare.bench.run_requests import REQUESTS
from pare.bench.runconfig import RunConfig
from pare.errors import UserInputError
from pare.output_paths import make_output_folder
from pare.results.records import EpisodeRecord
from pare.results.run_folder import (
    EPISODES,
    MANIFEST,
    MANIFEST_FORMAT,
    EpisodeKey,
    latest_records,
    read_manifest,
    read_records,
    scenario_hash,
    scenario_set_hash,
)
from pare.scenarios.model import Scenario

try:  # advisory locks exist on POSIX; elsewhere a run simply is not protected against a second writer
    import fcntl
except ImportError:  # pragma: no cover - Windows
    fcntl = None  # type: ignore[assignment]

CACHE_FILE = "model_calls.sqlite"
LOCK = ".lock"
WRITER_PROCESS = True
"""Store episodes through a writer process (on POSIX systems); False stores each one in the run's thread."""
PIPE_BYTES = 1 << 20
"""Room for finished episodes on their way to the writer (about 45 oracle episodes); when it is full, the
run waits for the writer."""
LOCK_WAIT_S = 3.0
"""How long opening a locked run folder waits for the lock: a killed run's writer may still be storing the
episodes it was sent."""
_WRITER_PROGRAM = _store_writer.__file__

PROVENANCE_PACKAGES = ("pydantic", "openai", "litellm", "ray", "jinja2", "rich", "typer", "dateparser")
"""The libraries whose versions a manifest records: they shape prompts, calls, runs, and (dateparser) how
checks read days and times in text."""


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


@dataclass
class RunStore:
    """The writer of one run folder, for one session of ``pare run``."""

    path: Path
    manifest: dict[str, Any]
    records: dict[EpisodeKey, EpisodeRecord] = field(default_factory=dict)
    hashes: dict[str, str] = field(default_factory=dict)
    """The content hash of every scenario of the run, by id (computed once, when the store is opened)."""
    _lock: IO[str] | None = None
    _writer: _WriterProcess | _InlineWriter | None = None
    _manifest_lock: threading.Lock = field(default_factory=threading.Lock)

    # -- opening -------------------------------------------------------------------------------------------
    @classmethod
    def open(
        cls,
        path: Path,
        config: RunConfig,
        scenarios: Mapping[str, Scenario],
        *,
        sweep_point: Mapping[str, Any] | None = None,
        extend_plan: bool = False,
    ) -> RunStore:
        """Open (or create) the run folder for ``config`` over ``scenarios``, ready to append.

        With ``extend_plan`` the manifest's plan keeps the scenarios and runs it already lists and adds
        these (``pare play`` records one scenario at a time); otherwise the plan is this configuration's.

        Refuses a folder made by a different configuration, or whose finished episodes ran a scenario
        that has changed since.
        """
        make_output_folder(path, "the run folder")
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
            store.manifest = _manifest(config, hashes, previous, sweep_point, extend_plan=extend_plan)
            store._write_manifest()
            store._writer = _start_writer(path, lock)
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

    def _write_manifest(self) -> None:
        with self._manifest_lock:  # one temporary file per manifest: writers take turns
            manifest = json.dumps(self.manifest, indent=2, ensure_ascii=False) + "\n"
            _store_writer.write_atomically(str(self.path / MANIFEST), manifest.encode("utf-8"))

    def record_requests(self, requests: Mapping[str, Any]) -> None:
        """Record in the manifest, per role, the request parameters the calls carry and every adjustment
        made to the configured ones (rewritten whole, atomically, each time one is learned: a run killed
        at any moment leaves the last record complete). Safe to call from any thread.
        """
        with self._manifest_lock:
            self.manifest = {**self.manifest, REQUESTS: redact_secrets(dict(requests))}
        self._write_manifest()

    # -- writing -------------------------------------------------------------------------------------------
    def done(self, key: EpisodeKey) -> bool:
        """Whether the episode already has a complete record."""
        record = self.records.get(key)
        return record is not None and record.complete

    def append(self, record: EpisodeRecord, trajectory: str | None = None) -> None:
        """Hand one finished episode to the writer: its trajectory (JSON text) is written first, then its
        line (the commit point). Returns at once, unless :data:`PIPE_BYTES` of episodes already wait; the
        episode counts as finished once :meth:`committed` returns it. Raises what stopped the writer.
        """
        if self._writer is None or self._writer.stopped:
            raise RuntimeError("the run store is closed")
        self._writer.check()
        path = record.trajectory if trajectory is not None else None
        data = (trajectory + "\n").encode("utf-8") if path and trajectory is not None else b""
        self._writer.put(record, path, data, (record.model_dump_json() + "\n").encode("utf-8"))
        self._writer.check()

    def committed(self) -> list[EpisodeRecord]:
        """The episodes whose lines were written since the last call, in the order they were written:
        only these count as finished (a run killed now keeps them).
        """
        if self._writer is None:
            return []
        written = self._writer.take_written()
        for record in written:
            current = self.records.get(record.key)
            if current is None or not current.complete:
                self.records[record.key] = record
        return written

    def flush(self) -> None:
        """Wait until every episode handed to :meth:`append` is written; raise what stopped the writer."""
        if self._writer is not None:
            self._writer.wait()
            self._writer.check()

    def close(self) -> None:
        """Write what is still waiting, force the episodes file to the disk and release the folder.
        Raises what stopped the writer, unless that was raised already. The episodes written meanwhile
        are still given by :meth:`committed`.
        """
        try:
            if self._writer is not None:
                self._writer.stop()
                self._writer.check()
        finally:
            if self._lock is not None:
                self._lock.close()
                self._lock = None

    def __enter__(self) -> RunStore:
        return self

    def __exit__(self, *exc_info: object) -> None:
        self.close()


def _start_writer(path: Path, lock: IO[str]) -> _WriterProcess | _InlineWriter:
    """The writer process where it can run (POSIX pipes, a Python to start it with), else the inline one."""
    if WRITER_PROCESS and os.name == "posix" and sys.executable and os.path.isfile(_WRITER_PROGRAM):
        with contextlib.suppress(OSError):  # it cannot be started: store in the run's thread instead
            return _WriterProcess(path, lock)
    return _InlineWriter(path)


class _WriterProcess:
    """The run's writer process (:mod:`pare.bench._store_writer`) and what it has stored.

    Episodes are sent as frames on its stdin (a full pipe makes the run wait: the queue is bounded); it
    answers one byte per episode stored, in order, so the records sent and not yet answered are exactly
    the episodes not yet finished. An error it meets is raised in the run's thread at its next call.
    """

    def __init__(self, path: Path, lock: IO[str] | None) -> None:
        self.path = path
        # It holds the run's lock too (the same open file): a run killed while episodes are still on their
        # way keeps its folder locked until they are written, so a resume never writes beside it.
        inherited = (lock.fileno(),) if lock is not None and fcntl is not None else ()
        self._process = subprocess.Popen(
            [sys.executable, "-I", "-S", _WRITER_PROGRAM, str(path)],
            stdin=subprocess.PIPE,
            stdout=subprocess.PIPE,
            pass_fds=inherited,
            start_new_session=True,  # Ctrl-C interrupts the run, which then lets the writer finish
        )
        assert self._process.stdin is not None and self._process.stdout is not None
        self._frames = self._process.stdin
        self._reply_pipe = self._process.stdout
        self._replies = self._reply_pipe.fileno()
        os.set_blocking(self._replies, False)
        with contextlib.suppress(OSError, AttributeError):  # Linux only: room for ~45 episodes, not 3
            fcntl.fcntl(self._frames.fileno(), fcntl.F_SETPIPE_SZ, PIPE_BYTES)
        self._sent: deque[EpisodeRecord] = deque()
        self._written: deque[EpisodeRecord] = deque()
        self._failure = b""
        """The writer's error reply, as read so far."""
        self._ended = False
        self._error: BaseException | None = None
        self._error_raised = False
        self.stopped = False

    def put(self, record: EpisodeRecord, trajectory_path: str | None, data: bytes, line: bytes) -> None:
        """Send one episode (waiting while the pipe is full)."""
        try:
            self._frames.write(_store_writer.frame(trajectory_path, data, line))
            self._frames.flush()
        except BrokenPipeError:  # the writer has stopped: its reply says why
            self._read(until_done=True)
            return
        self._sent.append(record)
        self._read(until_done=False)

    def take_written(self) -> list[EpisodeRecord]:
        """The records stored since the last call."""
        self._read(until_done=False)
        taken = list(self._written)
        self._written.clear()
        return taken

    def wait(self) -> None:
        """Return once every episode sent is stored (or the writer has stopped)."""
        self._read(until_done=True)

    def check(self) -> None:
        """Raise the error that stopped the writer, once."""
        if self._error is not None and not self._error_raised:
            self._error_raised = True
            raise self._error

    def stop(self) -> None:
        """Let the writer store what was sent and end (forcing the episodes file to the disk)."""
        if self.stopped:
            return
        self.stopped = True
        with contextlib.suppress(BrokenPipeError):
            self._frames.close()  # the end of its input: it writes what it has, then exits
        os.set_blocking(self._replies, True)
        while not self._ended:
            self._take(os.read(self._replies, 65536))
        self._reply_pipe.close()
        self._process.wait()

    def _read(self, *, until_done: bool) -> None:
        """Take the writer's replies that have arrived; with ``until_done``, wait until every episode sent
        is answered or the writer has ended.
        """
        while not self._ended:
            try:
                self._take(os.read(self._replies, 65536))
            except BlockingIOError:
                if not (until_done and self._sent) and not self._failure:
                    return
                select.select([self._replies], [], [])

    def _take(self, data: bytes) -> None:
        if not data:  # the writer ended: told to (stop), after an error reply, or killed
            self._ended = True
            if self._error is None and (not self.stopped or self._sent):
                self._error = RuntimeError(
                    f"{self.path}: the run's writer process ended unexpectedly "
                    f"(exit status {self._process.wait()}); run the same command again to resume"
                )
            return
        if self._failure:
            self._failure += data
        else:
            stored = data.find(_store_writer.FAILED)
            stored = len(data) if stored < 0 else stored
            for _ in range(stored):
                self._written.append(self._sent.popleft())
            self._failure = data[stored:]
        if self._failure.endswith(b"\n"):
            self._error = _writer_error(self.path, self._failure[1:].decode("utf-8", "replace"))
            self._failure = b""
            self._ended = True  # it stops after an error: the episodes still sent were not stored


class _InlineWriter:
    """The writer where no writer process can run (no POSIX pipes): stores each episode at once."""

    def __init__(self, path: Path) -> None:
        self.path = path
        self._episodes = _store_writer.EpisodesFile(str(path))
        self._made: set[str] = set()
        self._written: list[EpisodeRecord] = []
        self.stopped = False

    def put(self, record: EpisodeRecord, trajectory_path: str | None, data: bytes, line: bytes) -> None:
        """Store one episode now."""
        try:
            _store_writer.store(str(self.path), trajectory_path or "", data, line, self._episodes, self._made)
        except OSError as error:
            raise _writer_error(self.path, _store_writer.describe(error).decode()) from error
        self._written.append(record)

    def take_written(self) -> list[EpisodeRecord]:
        """The records stored since the last call."""
        taken, self._written = self._written, []
        return taken

    def wait(self) -> None:
        """Nothing waits."""

    def check(self) -> None:
        """Errors were raised by :meth:`put`."""

    def stop(self) -> None:
        """Force the episodes file to the disk and close it."""
        if not self.stopped:
            self.stopped = True
            self._episodes.close()


def _writer_error(path: Path, reply: str) -> Exception:
    """The error to raise for the writer's error reply (``errno<TAB>message<TAB>filename``)."""
    number, message, filename = [*reply.rstrip("\n").split("\t"), "", ""][:3]
    where = f" ({filename})" if filename else ""
    if number == "0":  # not a failure of the disk: a bug
        return RuntimeError(f"{path}: the run's writer failed: {message}{where}")
    return UserInputError(
        f"{path}: cannot write the run: {message}{where}. Every episode reported as finished is recorded; "
        "fix this and run the same command again to resume."
    )


def _acquire_lock(path: Path) -> IO[str]:
    handle = (path / LOCK).open("a", encoding="utf-8")
    if fcntl is not None:
        deadline = time.monotonic() + LOCK_WAIT_S
        while True:
            try:
                fcntl.flock(handle.fileno(), fcntl.LOCK_EX | fcntl.LOCK_NB)
                break
            except BlockingIOError:
                if time.monotonic() < deadline:
                    time.sleep(0.02)
                    continue
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
    *,
    extend_plan: bool = False,
) -> dict[str, Any]:
    planned, runs = dict(hashes), config.runs
    earlier = (previous or {}).get("plan")
    if extend_plan and isinstance(earlier, dict):
        planned = {**dict(earlier.get("scenarios") or {}), **planned}
        runs = max(runs, int(earlier.get("runs") or 1))
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
        "protocol": config.protocol.record(),
        "judge": redact_secrets(config.judge_provenance()),
        "policies": config.policy_names(),
        "sweep_point": dict(sweep_point or (previous or {}).get("sweep_point", {})),
        "plan": {"runs": runs, "scenarios": dict(sorted(planned.items()))},
        "scenario_set_hash": scenario_set_hash(planned),
        "provenance": provenance(),
        "sessions": sessions,
        # what the requests carried: the previous session's record until this session writes its own
        REQUESTS: dict((previous or {}).get(REQUESTS, {})),
    }
