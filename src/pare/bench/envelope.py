"""The changes a scenario's solutions make, found by playing them, kept per scenario content.

The envelope of :mod:`pare.scenarios.side_effects` is what the oracle and every passing variant change
when played by the oracle policies with the default settings (no tool failures, no noise): the same runs
the self-test gate plays, so the gate computes it from its own runs (:func:`remember`) and a run finds it
ready. It is kept in memory per process and on disk beside the parsed-scenario cache, under the
scenario's content hash and PARE's code fingerprint: a changed scenario or a changed PARE plays its
solutions again, once.
"""

from __future__ import annotations

import json
import os
import shutil
from collections.abc import Iterable, Sequence
from pathlib import Path

from pare.scenarios.model import Scenario
from pare.scenarios.parsed_cache import KEPT_VERSIONS, cache_folder
from pare.scenarios.side_effects import Change, Envelope

_KNOWN: dict[str, Envelope] = {}
"""Envelopes of this process, by :func:`_key`."""
_KEPT = 4096


def envelope_solutions(scenario: Scenario) -> list[str | None]:
    """The solutions whose changes make the envelope: the oracle (``None``) and each passing variant."""
    return scenario.right_solutions()


async def expected_envelope(scenario: Scenario) -> Envelope:
    """The envelope of ``scenario``: from memory, from disk, or by playing its solutions now."""
    same: Envelope | None = scenario.known(Envelope)
    if same is not None:
        return same
    key = _key(scenario)
    known = _KNOWN.get(key) or _read(key)
    if known is not None:
        return _keep(scenario, key, known)
    from pare.bench.episode import arun_episode  # the episode module asks this one for envelopes
    from pare.scenarios.oracle import OracleAssistant, OracleUser

    played: list[Sequence[Change]] = []
    for name in envelope_solutions(scenario):
        solution = scenario.solution(name)
        result = await arun_episode(
            scenario, OracleUser(scenario, solution), OracleAssistant(scenario, solution), side_effects=False
        )
        played.append(result.changes)
    return remember(scenario, played)


def remember(scenario: Scenario, played: Iterable[Sequence[Change]]) -> Envelope:
    """Keep the envelope of ``scenario`` made of the changes of its solutions' runs (all of
    :func:`envelope_solutions`, played with the default settings), and return it.
    """
    envelope = Envelope.of(played)
    key = _key(scenario)
    _write(key, envelope)
    return _keep(scenario, key, envelope)


def _keep(scenario: Scenario, key: str, envelope: Envelope) -> Envelope:
    if len(_KNOWN) >= _KEPT:  # a long-lived process loading scenarios again
        _KNOWN.clear()
    _KNOWN[key] = envelope
    return scenario.keep(Envelope, envelope)


def _key(scenario: Scenario) -> str:
    return scenario.content_hash()


def _folder() -> Path | None:
    scenarios = cache_folder()  # <root>/scenarios/<code fingerprint>
    return None if scenarios is None else scenarios.parent.parent / "envelopes" / scenarios.name


def _read(key: str) -> Envelope | None:
    folder = _folder()
    if folder is None:
        return None
    try:
        return Envelope.from_json(json.loads((folder / f"{key}.json").read_text(encoding="utf-8")))
    except (OSError, ValueError, TypeError):
        return None


def _write(key: str, envelope: Envelope) -> None:
    folder = _folder()
    if folder is None:
        return
    target = folder / f"{key}.json"
    temporary = target.with_name(f"{target.name}.{os.getpid()}.tmp")
    # the cache is a convenience: a run that cannot keep it computes the envelope again next time
    try:
        if not folder.exists():
            folder.mkdir(parents=True, exist_ok=True)
            _prune_siblings(folder)
        temporary.write_text(json.dumps(envelope.to_json()), encoding="utf-8")
        os.replace(temporary, target)
    except OSError:
        temporary.unlink(missing_ok=True)


def _prune_siblings(folder: Path) -> None:
    """Remove the folders of all but the most recent ``KEPT_VERSIONS`` other code versions."""
    siblings = sorted(
        (path for path in folder.parent.iterdir() if path.is_dir() and path != folder),
        key=lambda path: path.stat().st_mtime,
        reverse=True,
    )
    for stale in siblings[KEPT_VERSIONS:]:
        shutil.rmtree(stale, ignore_errors=True)
