"""A person in the user's seat (``pare play``): one episode of one scenario against the configured
assistant, recorded in a run folder like any other episode.

The configuration is a run configuration whose user policy is ``human`` (so the manifest, the label and
the identity say who played the user). Each session adds one episode: the next run index of the scenario
in the folder (run 1, then 2, ...), and the folder's plan grows to hold every scenario and run played in
it, so ``pare report`` and ``pare view`` read it as they read any run.

The episode is written when it ends, after its checks ran. A session left before then (``quit``, Ctrl-C,
the end of the input) writes nothing: no half-played episode is ever read as a result.
"""

from __future__ import annotations

import json
from dataclasses import dataclass, replace
from pathlib import Path

from pare.agents.policy import UserPolicy
from pare.bench.build import EpisodePlan, RunModels
from pare.bench.policies import HUMAN, Player
from pare.bench.runconfig import MAX_RUNS, RunConfig
from pare.bench.runner import EpisodeOutput, play_episode, select_scenarios
from pare.bench.store import RunStore
from pare.errors import UserInputError
from pare.results.run_folder import (
    EPISODES,
    MANIFEST,
    read_manifest,
    read_records,
    scenario_hash,
    trajectory_path,
)
from pare.scenarios.model import Scenario

PLAY_SETTINGS: tuple[tuple[str, object], ...] = (("policies.user", HUMAN), ("runs", 1), ("cache", "off"))
"""What ``pare play`` sets in every configuration: a person plays the user; one episode; no model-call
cache (the person's answers cannot be replayed, so neither can the assistant's calls that follow them)."""


@dataclass(frozen=True)
class Seat:
    """The episode a person is about to play, and where it will be recorded."""

    config: RunConfig
    plan: EpisodePlan
    folder: Path


def prepare(config: RunConfig) -> Seat:
    """The one scenario ``config`` selects, the run index its next episode takes in the run folder, and
    the folder.

    Raises:
        UserInputError: The user is not played by a person, the selection is not exactly one scenario, or
            the folder already holds the most runs a run may have.
    """
    if config.policy("user") != HUMAN:
        raise UserInputError(f"pare play puts a person in the user's seat: policies.user must be '{HUMAN}'")
    scenarios = select_scenarios(config)
    if len(scenarios) != 1:
        raise UserInputError(
            f"pare play plays one scenario at a time; the selection holds {len(scenarios)}: "
            f"{', '.join(sorted(scenarios)[:5])}"
        )
    scenario = next(iter(scenarios.values()))
    folder = config.output_dir()
    _check_folder(folder, config, scenario)
    run = next_run(folder, scenario.id)
    plan = EpisodePlan(scenario, run, config.episode_seed(scenario.id, run), scenario_hash(scenario))
    return Seat(config.model_copy(update={"runs": run}), plan, folder)


def _check_folder(folder: Path, config: RunConfig, scenario: Scenario) -> None:
    """Refuse, before the person plays, a folder the episode could not be recorded in: one made by another
    configuration, or holding episodes of an earlier version of the scenario (the store would refuse it
    once the episode is over, and the person's play would be lost).
    """
    manifest = folder / MANIFEST
    if not manifest.exists():
        return
    if read_manifest(manifest).get("identity") != config.identity():
        raise UserInputError(
            f"{folder} holds runs of another configuration (other assistant, protocol, world or seed), so "
            "the episode could not be recorded there; leave out --output to get this configuration's own "
            "folder, or choose another"
        )
    file = folder / EPISODES
    played = read_records(file) if file.exists() else []
    wanted = scenario_hash(scenario)
    if any(r.scenario_id == scenario.id and r.complete and r.scenario_hash != wanted for r in played):
        raise UserInputError(
            f"{folder} holds episodes of an earlier version of {scenario.id}, so the episode could not be "
            "recorded beside them; choose another --output"
        )


def next_run(folder: Path, scenario_id: str) -> int:
    """The run index of the next episode of ``scenario_id`` in ``folder``: one past the last recorded.

    Raises:
        UserInputError: The folder already holds the most runs of the scenario a run may have.
    """
    file = folder / EPISODES
    runs = (
        [record.run for record in read_records(file) if record.scenario_id == scenario_id]
        if file.exists()
        else []
    )
    run = max(runs, default=0) + 1
    if run > MAX_RUNS:
        raise UserInputError(
            f"{folder} already holds {MAX_RUNS} runs of {scenario_id}; choose another --output"
        )
    return run


async def play(seat: Seat, user: UserPolicy) -> EpisodeOutput:
    """Play the seat's episode with ``user`` (the person) against the configured assistant and judge.

    Raises:
        SeatLeft: The person left before the episode ended (nothing is recorded).
        RunFailure: A model provider stayed down (nothing is recorded).
        UserInputError: A mistake in the configuration (a key, a model, a policy).
    """
    config = seat.config
    models = RunModels.create(config, seat.folder)
    models.players = {
        "user": Player("user", HUMAN, lambda _context: user),
        "assistant": Player.resolve("assistant", config.policy("assistant")),
        "judge": Player.resolve("judge", config.policy("judge")),
    }
    try:
        return await play_episode(seat.plan, config, models)
    finally:
        await models.aclose()


def record(seat: Seat, output: EpisodeOutput) -> Path:
    """Write the played episode to the seat's run folder (the plan extended to hold it); the folder.

    Raises:
        UserInputError: The folder belongs to another configuration or cannot be written.
    """
    scenario: Scenario = seat.plan.scenario
    run = max(seat.plan.run, next_run(seat.folder, scenario.id))
    if run != seat.plan.run:  # another session recorded this run meanwhile: take the next one, keep both
        output = _renumbered(output, run)
    config = seat.config.model_copy(update={"runs": run})
    with RunStore.open(seat.folder, config, {scenario.id: scenario}, extend_plan=True) as store:
        store.append(output.record, output.trajectory)
        store.flush()
    return seat.folder


def _renumbered(output: EpisodeOutput, run: int) -> EpisodeOutput:
    """``output`` recorded as run ``run`` (its seed stays the one it was played with)."""
    record = output.record
    path = trajectory_path(record.scenario_id, run) if record.trajectory is not None else None
    trajectory = output.trajectory
    if trajectory is not None:
        data = json.loads(trajectory)
        data["run"] = run
        trajectory = json.dumps(data, ensure_ascii=False, allow_nan=False, separators=(",", ":"))
    return replace(
        output, record=record.model_copy(update={"run": run, "trajectory": path}), trajectory=trajectory
    )
