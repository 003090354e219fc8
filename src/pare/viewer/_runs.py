"""The run folders the viewer shows: configurations, their metrics and their episodes' summary rows.

Everything is read lazily and kept: a configuration's records when its table is first asked for, its
metrics when the runs page is, one trajectory at a time when an episode page is. A sweep of thousands of
episodes therefore costs its ``episodes.jsonl`` lines, never its trajectories, until one is opened.
"""

from __future__ import annotations

import json
from collections.abc import Iterable
from dataclasses import dataclass, field
from functools import cached_property
from pathlib import Path
from typing import Any

from pare.bench.metrics import ConfigurationMetrics, compute_metrics
from pare.bench.records import EpisodeRecord
from pare.bench.store import LoadedRun, load_run, run_folders
from pare.errors import UserInputError
from pare.viewer._paths import OutsideRunError, confined, slug

MAX_TRAJECTORY_BYTES = 64 * 1024 * 1024
"""The largest trajectory file the viewer opens."""

EpisodeKey = tuple[str, int]


@dataclass
class Configuration:
    """One run folder: a configuration with its episodes."""

    cid: str
    """Its id in URLs (unique among the folders given)."""
    path: Path

    @cached_property
    def loaded(self) -> LoadedRun:
        """The run as reports read it (manifest and one record per episode)."""
        return load_run(self.path)

    @property
    def label(self) -> str:
        """The configuration's name."""
        return self.loaded.label

    @property
    def sweep_point(self) -> dict[str, Any]:
        """The swept settings of this configuration (empty for a lone run)."""
        return self.loaded.sweep_point

    @cached_property
    def metrics(self) -> ConfigurationMetrics:
        """The headline numbers of ``pare report``."""
        run = self.loaded
        return compute_metrics(
            run.records, label=run.label, runs=run.runs, planned=run.planned, params=run.sweep_point
        )

    @cached_property
    def records(self) -> dict[EpisodeKey, EpisodeRecord]:
        """Every episode's record by (scenario, run), in that order."""
        return {record.key: record for record in self.loaded.records}

    @cached_property
    def by_slug(self) -> dict[tuple[str, int], EpisodeRecord]:
        """Records by (scenario slug, run): how URLs name episodes."""
        return {(slug(scenario), run): record for (scenario, run), record in self.records.items()}

    def record(self, scenario_slug: str, run: int) -> EpisodeRecord | None:
        """The record of one episode, named as in URLs."""
        return self.by_slug.get((scenario_slug, run))

    def trajectory(self, record: EpisodeRecord) -> dict[str, Any] | None:
        """The full trajectory of a complete episode, or ``None`` when it has none (failed episodes).

        Raises:
            OutsideRunError: The record names a file outside the run folder.
            UserInputError: The file is missing, too large or not a trajectory.
        """
        if record.trajectory is None:
            return None
        file = confined(self.path, record.trajectory)
        try:
            if file.stat().st_size > MAX_TRAJECTORY_BYTES:
                raise UserInputError(f"{file}: larger than {MAX_TRAJECTORY_BYTES} bytes; not opened")
            data = json.loads(file.read_bytes().decode("utf-8"))
        except (OSError, UnicodeDecodeError, json.JSONDecodeError) as error:
            raise UserInputError(f"{file}: cannot read the trajectory: {error}") from None
        if not isinstance(data, dict) or not isinstance(data.get("steps"), list):
            raise UserInputError(f"{file}: not a PARE trajectory (no steps)")
        return data


@dataclass
class Catalog:
    """The configurations of every run or sweep folder given to ``pare view``."""

    roots: list[Path]
    configurations: list[Configuration] = field(default_factory=list)

    @classmethod
    def open(cls, paths: Iterable[Path]) -> Catalog:
        """Find the run folders in ``paths`` (run folders, or sweep folders holding them).

        Raises:
            UserInputError: A path is not a run or sweep folder.
        """
        roots = [Path(path) for path in paths]
        if not roots:
            raise UserInputError("name at least one run or sweep folder")
        configurations: list[Configuration] = []
        taken: set[str] = set()
        for folder in run_folders(roots):
            cid = base = slug(folder.resolve().name)
            number = 2
            while cid in taken:
                cid, number = f"{base}-{number}", number + 1
            taken.add(cid)
            configurations.append(Configuration(cid, folder))
        for configuration in configurations:
            configuration.loaded  # noqa: B018 - read every manifest now, so a damaged folder is named at once
        return cls(roots=roots, configurations=configurations)

    def get(self, cid: str) -> Configuration | None:
        """The configuration with id ``cid``."""
        return next((c for c in self.configurations if c.cid == cid), None)


__all__ = ["Catalog", "Configuration", "OutsideRunError"]
