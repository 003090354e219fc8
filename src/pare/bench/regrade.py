"""Re-grading a run: its stored trajectories judged again with today's checks, into a new run folder.

When a scenario's checks are fixed (a reviewer found a correct solution rejected, or a wrong one
accepted), the runs already made still carry the old verdicts. Playing them again costs every model call
and gives other trajectories; re-grading keeps the trajectories and asks only the checks again: each
episode's final state is rebuilt from today's scenario start and the trajectory's state diff, and the
goals and side effects are evaluated on it and on its action log exactly as a finished episode is
(:func:`pare.bench.grading.grade`). No model is called but the judge of free-text checks (through the
model-call cache of the new folder, so a re-grade run again asks nothing it asked before).

The new folder names the original and both versions of every scenario; each record keeps the verdict it
had before (``regraded_from``) so reports and the viewer can say what changed. Scores before and after a
re-grade are not comparable: ``pare report`` refuses to put the two runs in one table unless told to.

An episode whose scenario's world changed since it was played (its start state hashes differently), or
that was stored before PARE kept what re-grading needs (format-1 trajectories: no state diff's start, no
full attribution), cannot be re-graded: it is carried over as missing coverage, with the reason.
"""

from __future__ import annotations

import asyncio
import json
import os
import shutil
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from pare.agents.models.config import ModelConfig
from pare.agents.models.ledger import UsageLedger
from pare.bench.build import EpisodeModel, RunModels
from pare.bench.grading import grade
from pare.bench.runconfig import Models, RunConfig
from pare.bench.store import CACHE_FILE, provenance
from pare.env import EnvConfig
from pare.errors import UserInputError
from pare.results.records import EpisodeRecord, Failure, PreviousVerdict, summarize
from pare.results.run_folder import (
    EPISODES,
    MANIFEST,
    LoadedRun,
    load_run,
    scenario_hash,
    scenario_set_hash,
    trajectory_path,
)
from pare.results.trajectory import OutcomeRecord, final_state, read_trajectory, write_trajectory
from pare.scenarios.build import build_environment
from pare.scenarios.checks import Judge
from pare.scenarios.library import library, load_scenarios
from pare.scenarios.model import Scenario

REGRADED_FROM = "regraded_from"
"""The manifest's key naming the run a re-graded folder was made from."""


@dataclass(frozen=True)
class Changed:
    """An episode whose verdict the re-grade changed."""

    scenario_id: str
    run: int
    was: bool
    now: bool
    goals: dict[str, tuple[bool, bool]]
    """The goals whose verdict changed: before, after."""


@dataclass
class RegradeSummary:
    """What a re-grade did."""

    source: Path
    path: Path
    regraded: int = 0
    carried: int = 0
    """Records carried over as they were: failed or missing in the original too."""
    changed: list[Changed] = field(default_factory=list)
    refused: list[tuple[str, int, str]] = field(default_factory=list)
    """Episodes that could not be re-graded: scenario, run, why."""
    judge: str | None = None


def default_output(source: Path) -> Path:
    """Where a re-grade of ``source`` goes unless told: beside it, ``<name>-regraded``."""
    return source.with_name(f"{source.name}-regraded")


def regrade_run(
    source: Path,
    output: Path,
    *,
    judge: ModelConfig | None = None,
    keep_judge: bool = True,
    scenario_paths: list[str] | None = None,
    on_episode: Callable[[], None] | None = None,
) -> RegradeSummary:
    """Re-grade the run in ``source`` into ``output`` (see the module's docstring).

    ``judge`` is the judge model of free-text checks; without it and with ``keep_judge``, the run's own
    judge (none: the checks' deterministic fallbacks). ``scenario_paths`` are scenario files to use instead
    of the library (by default, the paths the run was made from, else the library).

    Raises:
        UserInputError: ``source`` is not a run folder, ``output`` holds something other than a re-grade
            of ``source``, or a judge model cannot be set up.
    """
    loaded = load_run(source)
    if REGRADED_FROM in loaded.manifest:
        original_path = loaded.manifest[REGRADED_FROM].get("path")
        raise UserInputError(f"{source} is itself a re-grade of {original_path}; re-grade that run")
    _claim(output, source)
    original = _original_config(loaded)
    judge_config = (
        judge if judge is not None else (original.models.judge if keep_judge and original else None)
    )
    pool = _scenarios(scenario_paths, original)
    hashes = {sid: scenario_hash(pool[sid]) for sid in loaded.manifest["plan"]["scenarios"] if sid in pool}
    summary = RegradeSummary(source=source, path=output, judge=judge_config.model if judge_config else None)
    _write_manifest(output, loaded, hashes, judge_config)
    episodes = output / EPISODES
    episodes.unlink(missing_ok=True)  # a re-grade starts again: its answers are cheap, the cache keeps them

    async def regrade_all() -> None:
        models = _judge_models(judge_config, output)
        try:
            with episodes.open("a", encoding="utf-8") as lines:
                for record in loaded.records:
                    new = await _regrade_record(source, output, record, pool, models, summary)
                    lines.write(new.model_dump_json() + "\n")
                    lines.flush()
                    if on_episode is not None:
                        on_episode()
        finally:
            if models is not None:
                await models.aclose()

    asyncio.run(regrade_all())
    return summary


async def _regrade_record(
    source: Path,
    output: Path,
    record: EpisodeRecord,
    pool: Mapping[str, Scenario],
    models: RunModels | None,
    summary: RegradeSummary,
) -> EpisodeRecord:
    """One record re-graded (its trajectory written to ``output``), or carried over with the reason."""
    if not record.complete or record.trajectory is None:
        summary.carried += 1
        return record
    scenario = pool.get(record.scenario_id)
    if scenario is None:
        return _refused(record, summary, "the scenario is not in today's library or scenario files")
    trajectory = read_trajectory(source / record.trajectory)
    start = build_environment(scenario, EnvConfig(seed=record.seed)).snapshot()
    try:
        final = final_state(trajectory, start)
        attribution = trajectory.attribution_state()
    except ValueError as error:
        return _refused(record, summary, str(error))
    ledger = UsageLedger()
    judge = _episode_judge(models, f"{record.scenario_id}/run-{record.run}", ledger)
    outcome, _ = await grade(scenario, trajectory.log_entries(), start, final, attribution, judge=judge)
    regraded = trajectory.model_copy(
        update={
            "outcome": OutcomeRecord.model_validate(outcome.to_dict()),
            "scenario_hash": scenario_hash(scenario),
        }
    )
    path = trajectory_path(record.scenario_id, record.run)
    _write_atomically(output / path, write_trajectory(regraded))
    usage = {role: used for role, used in record.usage.items() if role != "judge"}
    usage.update(ledger.roles())
    fields = summarize(regraded, usage=usage)
    before = PreviousVerdict.of(record)
    new = record.model_copy(update={**fields, "scenario_hash": scenario_hash(scenario), "trajectory": path})
    new = new.model_copy(update={"regraded_from": before})
    summary.regraded += 1
    if before.success != new.success or before.goals != new.goals:
        goals = {
            goal: (before.goals.get(goal, False), passed)
            for goal, passed in new.goals.items()
            if before.goals.get(goal) != passed
        }
        summary.changed.append(Changed(record.scenario_id, record.run, before.success, new.success, goals))
    return new


def _refused(record: EpisodeRecord, summary: RegradeSummary, why: str) -> EpisodeRecord:
    summary.refused.append((record.scenario_id, record.run, why))
    return record.model_copy(
        update={
            "status": "failed",
            "failure": Failure(kind="not_regradable", message=why),
            "trajectory": None,
            "regraded_from": PreviousVerdict.of(record),
        }
    )


def _episode_judge(models: RunModels | None, namespace: str, ledger: UsageLedger) -> Judge | None:
    if models is None:
        return None
    from pare.agents.judge import ModelJudge

    client = models.clients["judge"]
    return ModelJudge(EpisodeModel(client, namespace, ledger), client.config.model)


def _judge_models(judge: ModelConfig | None, output: Path) -> RunModels | None:
    """The judge's client, with the new folder's model-call cache; none without a judge model."""
    if judge is None:
        return None
    config = RunConfig(models=Models(judge=judge), output=str(output))
    return RunModels.create(config, output)


def _original_config(loaded: LoadedRun) -> RunConfig | None:
    """The configuration the run was made with, as its manifest keeps it (``None`` if this PARE cannot
    read it back: the re-grade then uses the library and no judge unless told).
    """
    data = loaded.manifest.get("config")
    if not isinstance(data, dict):
        return None
    try:
        return RunConfig.model_validate(data)
    except ValueError:
        return None


def _scenarios(paths: list[str] | None, original: RunConfig | None) -> dict[str, Scenario]:
    chosen = paths or (original.scenarios.paths if original is not None else [])
    found = load_scenarios(chosen) if chosen else list(library().values())
    return {scenario.id: scenario for scenario in found}


def _claim(output: Path, source: Path) -> None:
    """Make ``output`` ready: new, or an earlier re-grade of ``source`` (whose answers cache is kept)."""
    if output.resolve() == source.resolve():
        raise UserInputError(f"{output}: a re-grade goes to a new folder, not over the run it re-grades")
    manifest = output / MANIFEST
    if manifest.exists():
        try:
            earlier = json.loads(manifest.read_text(encoding="utf-8")).get(REGRADED_FROM, {})
        except (OSError, ValueError, AttributeError):
            earlier = {}
        if Path(str(earlier.get("path", ""))).resolve() != source.resolve():
            raise UserInputError(
                f"{output} holds something other than a re-grade of {source}; choose another folder (-o)"
            )
        trajectories = output / "trajectories"
        if trajectories.exists():
            shutil.rmtree(trajectories)
    elif output.exists() and any(output.iterdir()):
        raise UserInputError(f"{output} is not empty; choose another folder for the re-grade (-o)")
    output.mkdir(parents=True, exist_ok=True)


def _write_manifest(
    output: Path, loaded: LoadedRun, hashes: Mapping[str, str], judge: ModelConfig | None
) -> None:
    manifest: dict[str, Any] = dict(loaded.manifest)
    before = manifest.get("plan", {})
    manifest.update(
        {
            "label": f"{loaded.label} (regraded)",
            "plan": {"runs": loaded.runs, "scenarios": dict(sorted(hashes.items()))},
            "scenario_set_hash": scenario_set_hash(hashes),
            "provenance": provenance(),
            REGRADED_FROM: {
                "path": str(loaded.path.resolve()),
                "label": loaded.label,
                "scenarios": dict(before.get("scenarios", {})) if isinstance(before, dict) else {},
                "scenario_set_hash": loaded.manifest.get("scenario_set_hash"),
                "judge": judge.model if judge is not None else None,
            },
        }
    )
    _write_atomically(output / MANIFEST, json.dumps(manifest, indent=2, sort_keys=True) + "\n")


def _write_atomically(path: Path, text: str) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    temporary = path.with_name(path.name + ".tmp")
    temporary.write_text(text, encoding="utf-8")
    os.replace(temporary, path)


__all__ = ["CACHE_FILE", "REGRADED_FROM", "Changed", "RegradeSummary", "default_output", "regrade_run"]
