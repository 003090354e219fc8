"""The output folder of ``pare generate``.

Its layout::

    DIR/manifest.json                    the batch's settings (checked when a batch resumes) and versions
    DIR/outcomes.jsonl                   one line per finished candidate: passed, duplicate or failed, why
    DIR/<id>.yaml                        each passing candidate, with a provenance header
    DIR/transcripts/<slot>/<stage>.json  every stage's conversation with the generator (and the judge's)
    DIR/model_calls.sqlite               the record/replay cache of model calls
    DIR/rejected/<id>.yaml, reviews.jsonl  what ``pare scenarios review`` set aside, and every decision

A candidate slot (``candidate-001`` ...) that has a line in ``outcomes.jsonl`` is finished and never
generated again; one cut short (a provider down, Ctrl-C) starts again from its first stage.
"""

from __future__ import annotations

import hashlib
import json
import os
import threading
import uuid
from datetime import UTC, datetime
from pathlib import Path
from typing import Any, Literal

from pydantic import BaseModel, ConfigDict, Field, ValidationError

from pare import __version__
from pare.bench.store import provenance
from pare.errors import UserInputError
from pare.generate.config import GenerateConfig
from pare.output_paths import make_output_folder
from pare.results.run_folder import MAX_EPISODES_BYTES, MAX_MANIFEST_BYTES, read_run_file
from pare.scenarios.schema import SCHEMA_FILE

MANIFEST = "manifest.json"
OUTCOMES = "outcomes.jsonl"
TRANSCRIPTS = "transcripts"
CACHE = "model_calls.sqlite"
PROVENANCE_PREFIX = "# provenance: "
Status = Literal["passed", "duplicate", "failed"]


class CandidateRecord(BaseModel):
    """How one candidate slot ended."""

    model_config = ConfigDict(extra="forbid", frozen=True)

    format: Literal[1] = 1
    slot: str
    index: int = Field(ge=1)
    status: Status
    scenario_id: str | None = None
    file: str | None = Field(default=None, description="The candidate's file, relative to the folder.")
    stage: str | None = Field(default=None, description="The stage it stopped at (failed or duplicate).")
    reason: str = ""
    problems: list[str] = Field(default_factory=list, description="The last problems the gate found.")
    attempts: dict[str, int] = Field(default_factory=dict, description="Model answers per stage.")
    transcripts: dict[str, str] = Field(default_factory=dict, description="Stage to its transcript's hash.")
    usage: dict[str, Any] = Field(default_factory=dict, description="Tokens and cost of its model calls.")
    seconds: float = 0.0


def slot_name(index: int) -> str:
    """The name of candidate slot ``index`` (from 1)."""
    return f"candidate-{index:03d}"


def transcript_hash(messages: list[dict[str, Any]]) -> str:
    """The hash of a conversation, as the provenance header records it."""
    text = json.dumps(messages, sort_keys=True, separators=(",", ":"), ensure_ascii=False)
    return "sha256:" + hashlib.sha256(text.encode("utf-8")).hexdigest()


def _write_atomically(path: Path, text: str) -> None:
    """Write ``text`` to a temporary file beside ``path``, then rename it: ``path`` is whole or absent.
    The temporary file's name is short and unique, whatever the length of ``path``'s (a name at the
    file system's limit would otherwise have no room for a suffix).
    """
    temporary = path.with_name(f".{uuid.uuid4().hex[:16]}.tmp")  # created as any file: the umask's mode
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        temporary.write_text(text, encoding="utf-8")
        os.replace(temporary, path)
    except OSError as error:  # a full disk, a read-only folder: never a half-written file
        temporary.unlink(missing_ok=True)
        raise _write_failure(path, error) from None
    except BaseException:
        temporary.unlink(missing_ok=True)
        raise


def _write_failure(path: Path, error: OSError) -> UserInputError:
    """The one-line error for a write the system refused (a full disk, a read-only folder)."""
    return UserInputError(
        f"{path}: cannot write it: {error.strerror or error}. Every candidate reported as finished is "
        "recorded; fix this and run the same command again to resume."
    )


class GenerationFolder:
    """The output folder of one configuration: what is finished, and where each piece is written."""

    def __init__(self, path: Path, config: GenerateConfig) -> None:
        self.path = path
        self.config = config
        self._lock = threading.Lock()
        self.records: dict[str, CandidateRecord] = {}

    @classmethod
    def open(cls, config: GenerateConfig) -> GenerationFolder:
        """Create the folder, or reopen it when it holds a batch of the same settings."""
        folder = cls(config.folder, config)
        manifest = folder.path / MANIFEST
        if manifest.exists():
            folder._check_same(manifest)
        make_output_folder(folder.path, "the candidates' folder")
        _write_atomically(
            manifest,
            json.dumps(
                {
                    "format": 1,
                    "kind": "pare-generate",
                    "identity": config.identity(),
                    "config": config.public_dict(),
                    "provenance": provenance(),
                },
                indent=2,
                ensure_ascii=False,
            )
            + "\n",
        )
        folder.records = {record.slot: record for record in folder.read_records()}
        return folder

    def _check_same(self, manifest: Path) -> None:
        text = read_run_file(manifest, "the generation manifest", max_bytes=MAX_MANIFEST_BYTES)
        try:
            before = json.loads(text).get("identity")
        except (json.JSONDecodeError, AttributeError) as error:
            raise UserInputError(f"{manifest}: not a generation manifest ({error})") from None
        now = json.loads(json.dumps(self.config.identity()))
        if before != now:
            changed = sorted(
                key for key in set(before or {}) | set(now) if (before or {}).get(key) != now.get(key)
            )
            raise UserInputError(
                f"{self.path} holds candidates generated with other settings ({', '.join(changed)} differ), "
                "so resuming would mix them. Use the original settings or another --output folder."
            )

    def read_records(self) -> list[CandidateRecord]:
        """Every well-formed line of the outcomes file (the latest per slot wins)."""
        file = self.path / OUTCOMES
        if not file.exists():
            return []
        records = []
        for line in read_run_file(file, "the outcomes file", max_bytes=MAX_EPISODES_BYTES).splitlines():
            try:
                records.append(CandidateRecord.model_validate_json(line))
            except ValidationError:
                continue  # an unfinished last line from a killed batch
        return records

    def done(self, slot: str) -> bool:
        """Whether slot ``slot`` finished in an earlier session."""
        return slot in self.records

    def record(self, record: CandidateRecord) -> None:
        """Append how one slot ended."""
        with self._lock:
            try:
                with (self.path / OUTCOMES).open("a", encoding="utf-8") as handle:
                    handle.write(record.model_dump_json() + "\n")
            except OSError as error:
                raise _write_failure(self.path / OUTCOMES, error) from None
            self.records[record.slot] = record

    def write_transcript(self, slot: str, stage: str, messages: list[dict[str, Any]], **extra: Any) -> str:
        """Keep one stage's conversation; return its hash."""
        digest = transcript_hash(messages)
        payload = {"slot": slot, "stage": stage, "hash": digest, **extra, "messages": messages}
        _write_atomically(
            self.path / TRANSCRIPTS / slot / f"{stage}.json",
            json.dumps(payload, indent=2, ensure_ascii=False) + "\n",
        )
        return digest

    def write_candidate(self, scenario_id: str, text: str, provenance_data: dict[str, Any]) -> str:
        """Write a passing candidate with its provenance header; return its file name."""
        name = f"{scenario_id}.yaml"
        header = candidate_header(provenance_data)
        _write_atomically(self.path / name, header + text)
        return name

    def taken_ids(self) -> set[str]:
        """Ids of the candidates already written to the folder (and set aside by review)."""
        ids = {path.stem for path in self.path.glob("*.yaml")}
        ids.update(path.stem for path in (self.path / "rejected").glob("*.yaml"))
        return ids


def candidate_header(data: dict[str, Any]) -> str:
    """The comment lines a candidate file starts with: the schema line for editors, what made it, and
    the provenance as one line of JSON (model, settings, the stage transcripts' hashes).
    """
    created = datetime.now(UTC).strftime("%Y-%m-%dT%H:%M:%SZ")
    return (
        f"# yaml-language-server: $schema={SCHEMA_FILE.resolve()}\n"
        f"# Generated by pare generate (PARE {__version__}) on {created}; "
        "review it with pare scenarios review.\n"
        f"{PROVENANCE_PREFIX}{json.dumps(data, separators=(', ', ': '), ensure_ascii=False)}\n"
    )


def read_provenance(text: str) -> dict[str, Any] | None:
    """The provenance header of a generated file, or ``None``."""
    for line in text.splitlines():
        if line.startswith(PROVENANCE_PREFIX):
            try:
                data = json.loads(line[len(PROVENANCE_PREFIX) :])
            except json.JSONDecodeError:
                return None
            return data if isinstance(data, dict) else None
        if line and not line.startswith("#"):
            break
    return None
