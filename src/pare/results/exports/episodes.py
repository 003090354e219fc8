"""What every exporter reads of a run: its complete episodes with their trajectories, and who played
each role. Trajectories are read here and only here, through :func:`pare.results.trajectory.read_trajectory`.
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping
from dataclasses import dataclass
from typing import Any

from pare.errors import UserInputError
from pare.results.records import EpisodeRecord
from pare.results.run_folder import LoadedRun
from pare.results.trajectory import Trajectory, read_trajectory


@dataclass(frozen=True)
class Episode:
    """One complete episode: its summary line and its trajectory."""

    record: EpisodeRecord
    trajectory: Trajectory


def complete_episodes(run: LoadedRun) -> Iterator[Episode]:
    """The run's complete episodes in (scenario, run) order, each with its trajectory.

    Raises:
        UserInputError: A record names a trajectory outside the run folder, or the file cannot be read.
    """
    base = run.path.resolve()
    for record in run.records:
        if not record.complete or record.trajectory is None:
            continue
        file = (base / record.trajectory).resolve()
        if not file.is_relative_to(base):  # the path comes from a file anyone may have edited
            raise UserInputError(
                f"{run.path}: episode {record.scenario_id} run {record.run} names a trajectory outside "
                f"the run folder ({record.trajectory!r})"
            )
        yield Episode(record, read_trajectory(file))


def role_players(manifest: Mapping[str, Any]) -> dict[str, str]:
    """Who played the user, the assistant and the judge: the model's name, else the policy's
    (``oracle``, ``deterministic``, a ``MODULE:FACTORY``), else ``unknown``.
    """
    identity = manifest.get("identity")
    models = identity.get("models") if isinstance(identity, dict) else None
    models = models if isinstance(models, dict) else {}
    policies = manifest.get("policies")
    policies = policies if isinstance(policies, dict) else {}
    judge = manifest.get("judge")

    def model(role: str) -> str | None:
        found = models.get(role)
        name = found.get("model") if isinstance(found, dict) else None
        return str(name) if name else None

    observe, execute = model("observe"), model("execute")
    assistant = observe if observe == execute or execute is None else f"{observe} / {execute}"
    judge_model = judge.get("model") if isinstance(judge, dict) else None
    return {
        "user": model("user") or str(policies.get("user") or "unknown"),
        "assistant": assistant or str(policies.get("assistant") or "unknown"),
        "judge": str(judge_model) if judge_model else str(policies.get("judge") or "unknown"),
    }


def manifest_text(manifest: Mapping[str, Any], *keys: str) -> str | None:
    """The string at ``keys`` inside the manifest, or ``None`` when a level is missing."""
    value: Any = manifest
    for key in keys:
        value = value.get(key) if isinstance(value, dict) else None
    return None if value is None else str(value)


def first_start(manifest: Mapping[str, Any]) -> str | None:
    """When the run's first session started (ISO 8601), as the manifest records it."""
    sessions = manifest.get("sessions")
    if isinstance(sessions, list) and sessions and isinstance(sessions[0], dict):
        started = sessions[0].get("started")
        return str(started) if started else None
    return None
