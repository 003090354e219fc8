"""A user calibration: every case played against the user under test, into one folder, resumable.

The user is chosen as in a run (``models.user`` and ``policies.user`` of a run configuration, its persona
of trust ``protocol.user_trust`` and the rest of the protocol); the scenarios too (``scenarios``). One
calibration is one folder (:mod:`pare.results.calibration` reads it): ``calibration.json``, then one line
per finished case in ``decisions.jsonl`` (the commit point) after its trajectory, and the model-call cache
``model_calls.sqlite`` (the run's record/replay cache: ``--cache replay`` reproduces a calibration without
calling a provider). Running the same calibration again keeps the cases recorded and plays the rest; a
case whose proposal or moment changed since (the scenario was edited) is played again. A folder made for
another user, persona or protocol is refused with the differences listed.
"""

from __future__ import annotations

import asyncio
import hashlib
import json
import os
import time
import traceback
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

from pare import __version__
from pare.agents.models.ledger import UsageLedger
from pare.agents.models.secrets import redact_secrets
from pare.bench._store_writer import write_atomically
from pare.bench.build import EpisodeModel, RunModels
from pare.bench.calibration.cases import (
    CASE_KINDS,
    PER_SCENARIO,
    CalibrationCase,
    CaseKind,
    calibration_cases,
)
from pare.bench.calibration.play import MAX_STEPS, play_case
from pare.bench.policies import MODEL_ROLES, Player, PolicyContext
from pare.bench.runconfig import RunConfig, slug
from pare.bench.runner import select_scenarios
from pare.bench.store import CACHE_FILE, provenance
from pare.errors import CacheMiss, RunFailure, UserInputError
from pare.output_paths import make_output_folder
from pare.results.calibration import (
    CALIBRATION_FORMAT,
    CALIBRATION_MANIFEST,
    DECISIONS_FILE,
    CaseRecord,
    read_records,
)

RETRY_PAUSE_S = 2.0


@dataclass(frozen=True)
class CalibrationSettings:
    """What a calibration plays beyond the run configuration: which cases, and the user's bound."""

    kinds: tuple[CaseKind, ...] = CASE_KINDS
    per_scenario: int = PER_SCENARIO
    """At most this many variants, mutants and tempting proposals each per scenario."""
    max_steps: int = MAX_STEPS
    """The user's actions on one case, its answer included."""

    def __post_init__(self) -> None:
        unknown = [kind for kind in self.kinds if kind not in CASE_KINDS]
        if unknown or not self.kinds:
            named = ", ".join(unknown) or "(none given)"
            raise UserInputError(f"unknown case kind {named}; the kinds are {', '.join(CASE_KINDS)}")
        if not 1 <= self.max_steps <= 50:
            raise UserInputError(f"the user's steps per case must be 1 to 50, not {self.max_steps}")
        if not 1 <= self.per_scenario <= 100:
            raise UserInputError(f"cases per kind and scenario must be 1 to 100, not {self.per_scenario}")


@dataclass
class CalibrationSummary:
    """What one session of a calibration did."""

    path: Path
    label: str
    planned: int
    played: int
    skipped: int
    failed: list[CaseRecord] = field(default_factory=list)
    seconds: float = 0.0


def calibration_label(config: RunConfig) -> str:
    """Who is calibrated: the user's policy (its model in brackets, or the model alone), and its persona
    of trust when it is not the default.
    """
    user = config.models.roles().get("user")
    policy = config.policy("user")
    who = user.model if user is not None and policy == "model" else policy
    if user is not None and policy != "model":
        who = f"{policy}[{user.model}]"
    trust = config.protocol.user_trust
    return f"{who} ({trust})" if trust != "demanding" else who


def calibration_identity(config: RunConfig, settings: CalibrationSettings) -> dict[str, Any]:
    """What shapes the user's decisions: its policy and model, the protocol (the persona of trust within
    it), the world's settings, the seed, and the user's bound per case.
    """
    identity = config.identity()
    return {
        "user": {"policy": config.policy("user"), "model": identity["models"].get("user")},
        "protocol": identity["protocol"],
        "world": identity["world"],
        "seed": identity["seed"],
        "max_steps": settings.max_steps,
    }


def calibration_folder(config: RunConfig, settings: CalibrationSettings) -> Path:
    """``output`` when given, else ``runs/calibrate-<label>-<identity hash>``."""
    if config.output:
        return Path(config.output)
    digest = hashlib.sha256(_canonical(calibration_identity(config, settings)).encode("utf-8")).hexdigest()
    return Path("runs") / f"calibrate-{slug(calibration_label(config))}-{digest[:10]}"


def plan_cases(config: RunConfig, settings: CalibrationSettings) -> list[CalibrationCase]:
    """The cases of the scenarios the configuration selects, in scenario order."""
    return [
        case
        for scenario in select_scenarios(config).values()
        for case in calibration_cases(scenario, kinds=settings.kinds, per_scenario=settings.per_scenario)
    ]


def case_hash(case: CalibrationCase) -> str:
    """A hash of what the case plays: its proposal and expected answer, and the scenario it is played in
    (its moment comes from the scenario's solution).
    """
    from pare.results.run_folder import scenario_hash

    text = _canonical({**case.identity(), "scenario": scenario_hash(case.scenario)})
    return hashlib.sha256(text.encode("utf-8")).hexdigest()[:16]


def run_calibration(
    config: RunConfig,
    settings: CalibrationSettings | None = None,
    *,
    on_case: Callable[[CaseRecord, int, int], None] | None = None,
) -> CalibrationSummary:
    """Play every case not yet recorded in the calibration's folder (see the module's docstring);
    ``on_case(record, done, total)`` is told of each case as it is recorded.
    """
    chosen = settings or CalibrationSettings()
    return asyncio.run(arun_calibration(config, chosen, on_case=on_case))


async def arun_calibration(
    config: RunConfig,
    settings: CalibrationSettings,
    *,
    on_case: Callable[[CaseRecord, int, int], None] | None = None,
) -> CalibrationSummary:
    """:func:`run_calibration` in a running event loop."""
    started = time.perf_counter()
    path = calibration_folder(config, settings)
    cases = plan_cases(config, settings)
    hashes = {case.case_id: case_hash(case) for case in cases}
    make_output_folder(path, "the calibration folder")
    previous = _open_manifest(path, config, settings)
    recorded = {r.case_id: r for r in read_records(path / DECISIONS_FILE)}
    todo = [
        case
        for case in cases
        if not (
            (done := recorded.get(case.case_id)) is not None
            and done.status == "complete"
            and done.case_hash == hashes[case.case_id]
        )
    ]
    _write_manifest(path, config, settings, len(cases), previous)
    summary = CalibrationSummary(path, calibration_label(config), len(cases), 0, len(cases) - len(todo))
    models = RunModels.create(config, path)
    player = Player.resolve("user", config.policy("user"))
    limit = asyncio.Semaphore(config.concurrency)
    done_count = summary.skipped

    async def one(case: CalibrationCase) -> None:
        nonlocal done_count
        async with limit:
            record, trajectory = await _play_with_retries(
                case, hashes[case.case_id], config, settings, models, player
            )
        _append(path, record, trajectory)
        summary.played += 1
        done_count += 1
        if record.status == "failed":
            summary.failed.append(record)
        if on_case is not None:
            on_case(record, done_count, len(cases))

    try:
        await asyncio.gather(*(one(case) for case in todo))
    finally:
        await models.aclose()
    summary.seconds = round(time.perf_counter() - started, 3)
    return summary


async def _play_with_retries(
    case: CalibrationCase,
    digest: str,
    config: RunConfig,
    settings: CalibrationSettings,
    models: RunModels,
    player: Player,
) -> tuple[CaseRecord, str | None]:
    attempt = 1
    while True:
        try:
            return await _play(case, digest, config, settings, models, player)
        except RunFailure as error:
            if attempt > config.episode_retries:
                return _failed(case, digest, f"provider unavailable: {error}"), None
            await asyncio.sleep(RETRY_PAUSE_S * 2 ** (attempt - 1))
            attempt += 1


async def _play(
    case: CalibrationCase,
    digest: str,
    config: RunConfig,
    settings: CalibrationSettings,
    models: RunModels,
    player: Player,
) -> tuple[CaseRecord, str | None]:
    ledger = UsageLedger()
    seed = config.episode_seed(case.case_id, 1)
    configs = config.models.roles()
    names = MODEL_ROLES["user"]
    context = PolicyContext(
        role="user",
        scenario=case.scenario,
        run=1,
        seed=seed,
        models={
            name: EpisodeModel(models.clients[name], case.case_id, ledger)
            for name in names
            if name in models.clients
        },
        model_configs={name: configs[name] for name in names if name in configs},
        max_format_retries=config.protocol.max_format_retries,
    )
    try:
        tested = player.build(context)
        outcome = await play_case(case, tested, config.episode_settings(seed), max_steps=settings.max_steps)
    except CacheMiss as error:
        return _failed(case, digest, f"cache miss: {error}"), None
    except (RunFailure, UserInputError):
        raise
    except Exception as error:  # a bug in PARE: keep going, keep the evidence
        detail = "".join(traceback.format_exception(error, limit=-8)).strip()
        return _failed(case, digest, f"internal error: {detail}"), None
    where = _trajectory_path(case)
    trajectory = {
        "format": 1,
        "label": calibration_label(config),
        "case": case.case_id,
        "seed": seed,
        **outcome.result.to_dict(),
    }
    record = CaseRecord(
        **_base(case, digest),
        status="complete",
        decision=outcome.decision,
        looked=outcome.looked,
        reason=outcome.reason,
        trajectory=where,
        usage=ledger.total().summary(),
    )
    return record, json.dumps(trajectory, ensure_ascii=False, allow_nan=False, separators=(",", ":"))


def _base(case: CalibrationCase, digest: str) -> dict[str, Any]:
    return {
        "case_id": case.case_id,
        "case_hash": digest,
        "scenario_id": case.scenario.id,
        "kind": case.kind,
        "name": case.name,
        "expected": case.expected,
        "proposal": case.proposal,
        "what": case.what,
        "apps": list(case.scenario.all_apps),
        "tags": list(case.scenario.tags),
    }


def _failed(case: CalibrationCase, digest: str, message: str) -> CaseRecord:
    return CaseRecord(**_base(case, digest), status="failed", failure=message)


def _trajectory_path(case: CalibrationCase) -> str:
    return f"trajectories/{case.scenario.id}/{slug(f'{case.kind}-{case.name}')}.json"


def _append(path: Path, record: CaseRecord, trajectory: str | None) -> None:
    """The trajectory first, then the record's line (the commit point), forced to the disk."""
    if trajectory is not None and record.trajectory is not None:
        file = path / record.trajectory
        file.parent.mkdir(parents=True, exist_ok=True)
        write_atomically(str(file), (trajectory + "\n").encode("utf-8"))
    with open(path / DECISIONS_FILE, "a", encoding="utf-8") as out:
        out.write(record.model_dump_json() + "\n")
        out.flush()
        os.fsync(out.fileno())


def _open_manifest(path: Path, config: RunConfig, settings: CalibrationSettings) -> dict[str, Any] | None:
    """The folder's manifest when it has one, checked to be this calibration's; ``None`` for a new folder.

    Raises:
        UserInputError: The folder is another calibration's, or not empty and no calibration's.
    """
    file = path / CALIBRATION_MANIFEST
    if not file.exists():
        strangers = sorted(p.name for p in path.iterdir() if p.name != CACHE_FILE)
        if strangers:
            raise UserInputError(
                f"{path} is not a calibration folder and is not empty ({', '.join(strangers[:3])}); "
                "choose another --output"
            )
        return None
    try:
        previous = json.loads(file.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as error:
        raise UserInputError(f"{file}: cannot read the calibration manifest: {error}") from None
    mine = calibration_identity(config, settings)
    theirs = previous.get("identity") if isinstance(previous, dict) else None
    if theirs != mine:
        differences = _differences(theirs if isinstance(theirs, Mapping) else {}, mine)
        raise UserInputError(
            f"{path} holds a calibration of another configuration ({'; '.join(differences)}); "
            "choose another --output, or leave it out for a folder of its own"
        )
    return dict(previous)


def _differences(old: Mapping[str, Any], new: Mapping[str, Any], where: str = "") -> list[str]:
    found: list[str] = []
    for key in sorted(set(old) | set(new)):
        name = f"{where}.{key}" if where else key
        before, after = old.get(key), new.get(key)
        if isinstance(before, Mapping) and isinstance(after, Mapping):
            found.extend(_differences(before, after, name))
        elif before != after:
            found.append(f"{name}: {json.dumps(before)} there, {json.dumps(after)} now")
    return found


def _write_manifest(
    path: Path,
    config: RunConfig,
    settings: CalibrationSettings,
    planned: int,
    previous: Mapping[str, Any] | None,
) -> None:
    sessions = list(previous.get("sessions", [])) if previous else []
    sessions.append({"started": datetime.now(UTC).isoformat(timespec="seconds"), "pare": __version__})
    user = config.models.roles().get("user")
    manifest = {
        "format": CALIBRATION_FORMAT,
        "kind": "calibration",
        "label": calibration_label(config),
        "identity": calibration_identity(config, settings),
        "user": {
            "policy": config.policy("user"),
            "model": redact_secrets(user.public_dict()) if user is not None else None,
        },
        "protocol": config.protocol.record(),
        "cases": {"kinds": list(settings.kinds), "per_scenario": settings.per_scenario},
        "cases_planned": planned,
        "provenance": provenance(),
        "sessions": sessions,
    }
    text = json.dumps(manifest, indent=2, ensure_ascii=False) + "\n"
    write_atomically(str(path / CALIBRATION_MANIFEST), text.encode("utf-8"))


def _canonical(value: Any) -> str:
    return json.dumps(value, sort_keys=True, separators=(",", ":"), ensure_ascii=False)
