"""A cache of parsed and validated scenario files, so that a process does not read YAML it has read before.

Reading a scenario (YAML composition, line bookkeeping, model and meaning validation) costs several
milliseconds; a benchmark of 150 scenarios paid about a second of that in every ``pare`` process. A file
that loaded without a problem is stored as the JSON of its model, under the hash of its text and of PARE's
own code: any change to the file or to PARE (a stricter check, a new field) misses the cache and reads the
file again. Only valid scenarios are stored, so every error is still found by the loader with its line.
The entries are plain JSON read back through the model's validation (dates and times that YAML read as
such are tagged, so they come back as the same objects); nothing in them can run code.

The cache lives in ``$PARE_CACHE_DIR`` (default ``$XDG_CACHE_HOME/pare``, else ``~/.cache/pare``) under
``scenarios/``; ``PARE_CACHE_DIR=off`` turns it off. It is never required: a folder that cannot be written
or an entry that cannot be read is passed over.
"""

from __future__ import annotations

import functools
import hashlib
import json
import os
import shutil
from dataclasses import dataclass
from datetime import date, datetime, time
from enum import Enum
from pathlib import Path
from typing import Any

from pydantic import ValidationError

from pare.scenarios.model import Scenario, Variant, validate_variants

_PACKAGE = Path(__file__).resolve().parents[1]


def cache_folder() -> Path | None:
    """Where parsed scenarios are kept, or ``None`` when the cache is off."""
    chosen = os.environ.get("PARE_CACHE_DIR")
    if chosen is not None and chosen.strip().lower() in ("", "off", "0", "none"):
        return None
    if chosen:
        root = Path(chosen)
    else:
        root = Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache") / "pare"
    return root / "scenarios" / code_fingerprint()


@functools.cache
def code_fingerprint() -> str:
    """A hash of PARE's source files: what decides how a scenario file parses and validates."""
    digest = hashlib.sha256()
    for file in sorted(_PACKAGE.rglob("*.py")):
        digest.update(file.relative_to(_PACKAGE).as_posix().encode())
        digest.update(file.read_bytes())
    return digest.hexdigest()[:20]


def _entry(folder: Path, text: str) -> Path:
    return folder / f"{hashlib.sha256(text.encode('utf-8')).hexdigest()}.json"


def cached(text: str) -> Scenario | None:
    """The scenario parsed from ``text`` before, if the cache holds it.

    An entry is two lines of JSON: the scenario's content hash and its fields but the variants, then its
    variants, read only when the scenario's variants are (:meth:`Scenario.with_deferred_variants`).
    """
    folder = cache_folder()
    if folder is None:
        return None
    try:
        head, _, variants = _entry(folder, text).read_text(encoding="utf-8").partition("\n")
        entry = json.loads(head, object_hook=_untag)
        later = _Variants(variants, text) if entry["variants"] else None
        return Scenario.with_deferred_variants(entry["scenario"], later, entry["hash"])
    except (OSError, ValidationError, ValueError, TypeError, KeyError):
        return None


@dataclass(frozen=True, slots=True)
class _Variants:
    """A cache entry's variants as stored, read when asked for (picklable, as a scenario must be); if the
    entry cannot give them, they are read from the file's text (the cache never stands in the way).
    """

    stored: str
    source: str

    def __call__(self) -> list[Variant]:
        try:
            return validate_variants(json.loads(self.stored, object_hook=_untag))
        except (ValidationError, ValueError, TypeError):
            from pare.scenarios.loader import parse_scenario  # the loader uses this module

            return parse_scenario(self.source).variants


def remember(text: str, scenario: Scenario) -> None:
    """Keep ``scenario`` (parsed from ``text`` without a problem) for the next process."""
    folder = cache_folder()
    if folder is None:
        return
    entry = _entry(folder, text)
    try:
        if not folder.exists():
            folder.mkdir(parents=True, exist_ok=True)
            _prune_siblings(folder)
        temporary = entry.with_name(f"{entry.name}.{os.getpid()}.tmp")
        data = scenario.model_dump(exclude_unset=True)
        variants = data.pop("variants", None)
        head = {"hash": scenario.content_hash(), "variants": variants is not None, "scenario": data}
        lines = [json.dumps(part, default=_tag, ensure_ascii=False) for part in (head, variants)]
        temporary.write_text("\n".join(lines), encoding="utf-8")
        os.replace(temporary, entry)
    except OSError:
        return


KEPT_VERSIONS = 4
"""Folders of older PARE code kept beside the current one; older ones are removed (each edit of PARE's code
starts a new folder, so a developer's cache would otherwise grow without end)."""


def _prune_siblings(folder: Path) -> None:
    """Remove the cache folders of all but the most recent :data:`KEPT_VERSIONS` other code versions."""
    siblings = [p for p in folder.parent.iterdir() if p.is_dir() and p != folder]
    siblings.sort(key=lambda p: p.stat().st_mtime, reverse=True)
    for stale in siblings[KEPT_VERSIONS:]:
        shutil.rmtree(stale, ignore_errors=True)


_TAGS: dict[str, Any] = {"$datetime": datetime, "$date": date, "$time": time}


def _tag(value: object) -> object:
    """JSON for what YAML and the model hold beyond JSON: dates and times (tagged), enums and sets."""
    for tag, kind in _TAGS.items():  # datetime before date: a datetime is a date too
        if isinstance(value, kind):
            return {tag: value.isoformat()}
    if isinstance(value, Enum):
        return value.value
    if isinstance(value, set | frozenset | tuple):
        return list(value)
    raise TypeError(f"cannot keep a {type(value).__name__} in the scenario cache")


def _untag(mapping: dict[str, Any]) -> Any:
    if len(mapping) == 1:
        ((key, value),) = mapping.items()
        kind = _TAGS.get(key)
        if kind is not None and isinstance(value, str):
            return kind.fromisoformat(value)
    return mapping
