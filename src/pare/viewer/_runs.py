"""The run folders the viewer shows: configurations, their metrics and their episodes' summary rows.

Everything is read lazily and kept: a configuration's records when its table is first asked for, its
metrics when the runs page is, one trajectory at a time when an episode page is. A sweep of thousands of
episodes therefore costs its ``episodes.jsonl`` lines, never its trajectories, until one is opened.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass, field
from functools import cached_property
from pathlib import Path
from typing import Any

from pare.errors import UserInputError
from pare.results.metrics import ConfigurationMetrics, compute_metrics
from pare.results.records import EpisodeRecord
from pare.results.run_folder import EPISODES, MANIFEST, LoadedRun, load_run, run_folders
from pare.results.trajectory import Trajectory, read_trajectory
from pare.viewer._paths import OutsideRunError, confined, slug

EpisodeKey = tuple[str, int]


@dataclass
class _Contents:
    """What one reading of a run folder gave, with what is derived from it on demand."""

    loaded: LoadedRun

    @cached_property
    def records(self) -> dict[EpisodeKey, EpisodeRecord]:
        return {record.key: record for record in self.loaded.records}

    @cached_property
    def by_slug(self) -> dict[tuple[str, int], EpisodeRecord]:
        return {(slug(scenario), run): record for (scenario, run), record in self.records.items()}

    @cached_property
    def metrics(self) -> ConfigurationMetrics:
        run = self.loaded
        return compute_metrics(
            run.records, label=run.label, runs=run.runs, planned=run.planned, params=run.sweep_point
        )


@dataclass
class Configuration:
    """One run folder: a configuration with its episodes.

    The folder is read again when its manifest or episodes file changed, so a run still being written
    shows its new episodes on the next page.
    """

    cid: str
    """Its id in URLs (unique among the folders given)."""
    path: Path
    _contents: _Contents | None = field(default=None, repr=False)
    _stamp: tuple[int, ...] = field(default=(), repr=False)

    def _current(self) -> _Contents:
        stamp = tuple(number for name in (MANIFEST, EPISODES) for number in _stat(self.path / name))
        if self._contents is None or stamp != self._stamp:
            self._contents, self._stamp = _Contents(load_run(self.path)), stamp
        return self._contents

    @property
    def loaded(self) -> LoadedRun:
        """The run as reports read it (manifest and one record per episode)."""
        return self._current().loaded

    @property
    def label(self) -> str:
        """The configuration's name."""
        return self.loaded.label

    @property
    def policies(self) -> dict[str, str]:
        """Who played each role (user, assistant, judge), as the manifest records it (empty for a run made
        before policies were recorded).
        """
        recorded = self.loaded.manifest.get("policies")
        if not isinstance(recorded, dict):
            return {}
        return {str(role): str(name) for role, name in recorded.items()}

    @property
    def sweep_point(self) -> dict[str, Any]:
        """The swept settings of this configuration (empty for a lone run)."""
        return self.loaded.sweep_point

    @property
    def metrics(self) -> ConfigurationMetrics:
        """The headline numbers of ``pare report``."""
        return self._current().metrics

    @property
    def records(self) -> dict[EpisodeKey, EpisodeRecord]:
        """Every episode's record by (scenario, run), in that order."""
        return self._current().records

    def record(self, scenario_slug: str, run: int) -> EpisodeRecord | None:
        """The record of one episode, named as in URLs."""
        return self._current().by_slug.get((scenario_slug, run))

    def trajectory(self, record: EpisodeRecord) -> Trajectory | None:
        """The full trajectory of a complete episode (older formats upgraded), or ``None`` when it has
        none (failed episodes).

        Raises:
            OutsideRunError: The record names a file outside the run folder.
            UserInputError: The file is missing, too large, of a newer format, or damaged.
        """
        if record.trajectory is None:
            return None
        return read_trajectory(confined(self.path, record.trajectory))


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
            configuration.loaded  # noqa: B018 - read every folder now, so a damaged one is named at once
        return cls(roots=roots, configurations=configurations)

    def get(self, cid: str) -> Configuration | None:
        """The configuration with id ``cid``."""
        return next((c for c in self.configurations if c.cid == cid), None)


def _stat(file: Path) -> tuple[int, int]:
    """When a file last changed and its size (zeros when it does not exist)."""
    try:
        status = file.stat()
    except FileNotFoundError:
        return (0, 0)
    return (status.st_mtime_ns, status.st_size)


__all__ = ["Catalog", "Configuration", "OutsideRunError"]
