"""A content-addressed record/replay cache of model calls, in one sqlite file.

The key is the SHA-256 of the canonical JSON of everything that shapes the answer (backend, model,
the request parameters the configuration sets, tools sent, messages) and nothing that does not
(endpoint, key, timeouts, retries), so a run recorded against one server replays anywhere. Several
asyncio tasks and several processes may share one file: it is in WAL mode with a busy timeout, each
operation is one short autocommit transaction, and writes are ``INSERT OR IGNORE`` (the first answer
stored for a key is the one kept). Each thread of each process keeps one open connection (opening one
per call cost more than the lookup itself).

A file that is not a cache, or is damaged, is a :class:`~pare.errors.UserInputError` that names it and
says what is wrong, as is a write the disk refuses (full): the run stops cleanly and resumes once it is
fixed. One stored answer that cannot be read is a miss (it is asked again and stored anew) or, when
replaying, a :class:`~pare.errors.CacheMiss` that names its key. Closing the cache folds the write-ahead
log into the file, so ``model_calls.sqlite`` alone holds every answer.
"""

from __future__ import annotations

import hashlib
import json
import logging
import os
import sqlite3
import threading
import time
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from datetime import UTC, datetime
from pathlib import Path
from typing import Any, Literal

from pydantic import ValidationError

from pare.agents.models.config import ModelConfig
from pare.agents.models.secrets import redact_secrets
from pare.agents.models.types import ChatMessage, Completion
from pare.errors import CacheMiss, UserInputError, did_you_mean

logger = logging.getLogger("pare.models")

CacheMode = Literal["off", "read_write", "replay"]
"""``off``: always call. ``read_write``: replay what is stored, call and store the rest. ``replay``: replay
only; a call that is not stored is an error (:class:`pare.errors.CacheMiss`)."""

CACHE_MODES: tuple[CacheMode, ...] = ("off", "read_write", "replay")
KEY_VERSION = 1
"""Part of every key: bump it when the key's recipe changes so old entries are not misread."""

_SCHEMA = """
CREATE TABLE IF NOT EXISTS completions (
    key TEXT PRIMARY KEY,
    backend TEXT NOT NULL,
    model TEXT NOT NULL,
    role TEXT NOT NULL,
    created_at TEXT NOT NULL,
    request TEXT NOT NULL,
    completion TEXT NOT NULL
)
"""
_COLUMNS = frozenset({"key", "backend", "model", "role", "created_at", "request", "completion"})
_BUSY = ("locked", "busy")
"""Words of sqlite's messages for a file another connection holds for the moment: waited for, not fatal."""


def canonical_json(value: Any) -> str:
    """Serialise ``value`` the same way every time (sorted keys, no spaces, UTF-8 kept)."""
    return json.dumps(value, sort_keys=True, separators=(",", ":"), ensure_ascii=False, allow_nan=False)


def request_record(
    config: ModelConfig,
    messages: Sequence[ChatMessage],
    tools: Sequence[dict[str, Any]] | None,
    namespace: str | None = None,
) -> dict[str, Any]:
    """Return what identifies a request: the parts of it that can change the model's answer.

    ``namespace`` separates requests that are identical but must be answered independently: the k runs
    of one scenario send the same first prompt, and each run must get its own sample, not a replay of
    run 1's.
    """
    # The configured parameters, not those a request ends up carrying: what a provider refuses is learnt
    # during a run, and a replay (which calls no provider) must find the same keys.
    record = {
        "version": KEY_VERSION,
        "backend": config.backend,
        "model": config.model,
        "params": config.request_params(),
        "tools": list(tools) if tools else None,
        "messages": [message.model_dump(mode="json", exclude_none=True) for message in messages],
    }
    if namespace is not None:
        record["namespace"] = namespace
    return record


def cache_key(record: dict[str, Any]) -> str:
    """Return the SHA-256 hex digest of the record's canonical JSON."""
    return hashlib.sha256(canonical_json(record).encode("utf-8")).hexdigest()


class ModelCallCache:
    """The record/replay store of model calls: one sqlite file, shared safely by tasks and processes."""

    def __init__(
        self, path: str | Path, mode: CacheMode = "read_write", *, busy_timeout_s: float = 30.0
    ) -> None:
        if mode not in CACHE_MODES:
            raise UserInputError(
                f"unknown cache mode '{mode}'.{did_you_mean(mode, CACHE_MODES)} "
                f"Choose one of {', '.join(CACHE_MODES)}."
            )
        self.path = Path(path)
        self.mode: CacheMode = mode
        self.busy_timeout_s = busy_timeout_s
        self._local = threading.local()
        self._opened: list[sqlite3.Connection] = []
        self._opened_lock = threading.Lock()
        if mode != "off":
            self._initialise()

    def __repr__(self) -> str:
        return f"ModelCallCache({str(self.path)!r}, mode={self.mode!r})"

    @property
    def reads(self) -> bool:
        """Whether stored answers are replayed."""
        return self.mode != "off"

    @property
    def writes(self) -> bool:
        """Whether new answers are stored."""
        return self.mode == "read_write"

    @contextmanager
    def _connect(self) -> Iterator[sqlite3.Connection]:
        # One connection per thread (asyncio.to_thread runs calls on a pool) and per process (a forked
        # worker must not share its parent's connection), opened on first use and kept.
        connection: sqlite3.Connection | None = getattr(self._local, "connection", None)
        if connection is None or getattr(self._local, "pid", None) != os.getpid():
            connection = sqlite3.connect(
                self.path, timeout=self.busy_timeout_s, isolation_level=None, check_same_thread=False
            )
            connection.execute(f"PRAGMA busy_timeout = {int(self.busy_timeout_s * 1000)}")
            # In WAL mode NORMAL syncs at checkpoints, not at every commit: a killed process loses no
            # committed answer (only a power cut could), and each put stops paying for an fsync.
            connection.execute("PRAGMA synchronous = NORMAL")
            self._local.connection, self._local.pid = connection, os.getpid()
            with self._opened_lock:
                self._opened.append(connection)
        yield connection

    def close(self) -> None:
        """Fold the write-ahead log into the file and close every connection this cache opened (it
        reopens on the next use): after a clean exit, copying ``model_calls.sqlite`` alone copies it all.
        """
        with self._opened_lock:
            opened, self._opened = self._opened, []
        if opened and self.writes:
            try:  # a process still writing keeps its part in the log; its own close folds it in
                opened[0].execute("PRAGMA wal_checkpoint(TRUNCATE)")
            except sqlite3.DatabaseError as error:
                logger.warning(
                    "the model-call cache %s: could not fold its log into the file: %s", self.path, error
                )
        for connection in opened:  # each was used by one thread only; closing from here is safe
            connection.close()
        self._local = threading.local()

    def _failure(self, error: sqlite3.DatabaseError, doing: str) -> UserInputError:
        """The clear error for a database failure: the disk refused a write, or the file is damaged."""
        text = str(error)
        if isinstance(error, sqlite3.OperationalError) and any(word in text for word in _BUSY):
            return UserInputError(
                f"the model-call cache {self.path}: cannot {doing}: another process held it for more than "
                f"{self.busy_timeout_s:g} s ({text})"
            )
        if "full" in text or (isinstance(error, sqlite3.OperationalError) and "disk" in text):
            return UserInputError(
                f"the model-call cache {self.path}: cannot {doing}: {text}. Free space (or move the cache) "
                "and run the same command again to resume."
            )
        return UserInputError(
            f"the model-call cache {self.path} is damaged or not a PARE cache ({text}); "
            "move it aside to record a new one, or restore a sound copy"
        )

    def _initialise(self) -> None:
        if self.mode == "replay" and not self.path.exists():
            raise UserInputError(
                f"the model-call cache {self.path} does not exist: replay needs a recorded cache "
                "(record one with cache mode read_write)"
            )
        self.path.parent.mkdir(parents=True, exist_ok=True)
        deadline = time.monotonic() + self.busy_timeout_s
        while True:
            try:
                with self._connect() as connection:
                    # WAL is a property of the file: once set by any process it stays set.
                    mode = connection.execute("PRAGMA journal_mode = WAL").fetchone()[0]
                    connection.execute(_SCHEMA)
                    columns = {str(row[1]) for row in connection.execute("PRAGMA table_info(completions)")}
                if not columns >= _COLUMNS:
                    raise UserInputError(
                        f"the model-call cache {self.path} is not a PARE cache: its table 'completions' "
                        f"lacks {', '.join(sorted(_COLUMNS - columns))}; move it aside to record a new one"
                    )
                if str(mode).lower() == "wal" or time.monotonic() > deadline:
                    return
            except sqlite3.DatabaseError as error:
                busy = isinstance(error, sqlite3.OperationalError) and any(w in str(error) for w in _BUSY)
                if not busy or time.monotonic() > deadline:
                    self.close()
                    raise self._failure(error, "open it") from None
            time.sleep(0.01)

    def get(self, key: str) -> Completion | None:
        """Return the stored completion for ``key`` (marked ``from_cache``), or ``None``."""
        if not self.reads:
            return None
        try:
            with self._connect() as connection:
                row = connection.execute(
                    "SELECT completion FROM completions WHERE key = ?", (key,)
                ).fetchone()
        except sqlite3.DatabaseError as error:
            raise self._failure(error, "read it") from None
        if row is None:
            return None
        try:
            return Completion.model_validate_json(row[0]).model_copy(update={"from_cache": True})
        except (ValidationError, TypeError, ValueError) as error:
            self._forget_damaged(key, error)
            return None

    def _forget_damaged(self, key: str, error: Exception) -> None:
        """A stored answer that cannot be read: an error when replaying, else forgotten (asked again)."""
        reason = " ".join(str(error).split())[:200]
        if self.mode == "replay":
            raise CacheMiss(
                f"the model-call cache {self.path}: the answer stored under key {key} is damaged ({reason}); "
                "a replay cannot ask the model again: record the run again with cache mode read_write"
            )
        logger.warning(
            "the model-call cache %s: the answer stored under key %s is damaged (%s); asking the model again",
            self.path,
            key,
            reason,
        )
        try:
            with self._connect() as connection:
                connection.execute("DELETE FROM completions WHERE key = ?", (key,))
        except sqlite3.DatabaseError as failure:
            raise self._failure(failure, "replace a damaged answer") from None

    def put(self, key: str, completion: Completion, *, request: dict[str, Any], role: str) -> bool:
        """Store ``completion`` under ``key`` unless an answer is already stored; return whether stored."""
        if not self.writes:
            return False
        stored = completion.model_copy(update={"from_cache": False}).model_dump_json()
        try:
            return self._insert(key, stored, request, role)
        except sqlite3.DatabaseError as error:
            raise self._failure(error, "store an answer") from None

    def _insert(self, key: str, stored: str, request: dict[str, Any], role: str) -> bool:
        with self._connect() as connection:
            cursor = connection.execute(
                "INSERT OR IGNORE INTO completions "
                "(key, backend, model, role, created_at, request, completion) VALUES (?, ?, ?, ?, ?, ?, ?)",
                (
                    key,
                    str(request.get("backend", "")),
                    str(request.get("model", "")),
                    role,
                    datetime.now(UTC).isoformat(timespec="seconds"),
                    canonical_json(redact_secrets(request)),  # the key is a hash: it keeps nothing
                    stored,
                ),
            )
            return cursor.rowcount == 1

    def __len__(self) -> int:
        if self.mode == "off":
            return 0
        with self._connect() as connection:
            return int(connection.execute("SELECT COUNT(*) FROM completions").fetchone()[0])

    def integrity_check(self) -> str:
        """Return sqlite's verdict on the file ('ok' when sound)."""
        with self._connect() as connection:
            return str(connection.execute("PRAGMA integrity_check").fetchone()[0])
