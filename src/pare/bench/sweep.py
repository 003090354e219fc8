"""A grid of run configurations into one folder: robustness sweeps and model-against-model tables.

A sweep file holds a ``base`` run configuration (inline, or the path of a run configuration file) and a
``grid``: dotted setting paths, each with the values to try. Every combination is one run, in its own
sub-folder named after its values, with the values recorded in its manifest (``sweep_point``), so
``pare report`` and ``pare plot`` can put them side by side. Re-running a sweep resumes each point.

.. code-block:: yaml

    base: {runs: 4, models: {user: {model: gpt-5-mini}}}
    grid:
      world.tool_failure_probability: [0.0, 0.1, 0.2, 0.4]
      models.assistant:
        - {model: claude-sonnet-4-5, backend: litellm}
        - {model: gpt-5}
    output: runs/tool-failures
"""

from __future__ import annotations

import copy
import itertools
import json
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from pydantic import BaseModel, ConfigDict, Field, ValidationError, field_validator

from pare.bench.runconfig import RunConfig, build_config, read_config_file, set_path, slug
from pare.bench.runner import ProgressSink, RunSummary, run_benchmark
from pare.errors import UserInputError
from pare.output_paths import make_output_folder
from pare.results.run_folder import SWEEP_FILE


class SweepSpec(BaseModel):
    """A sweep: the base configuration, the grid, and the folder that holds every point's run."""

    model_config = ConfigDict(extra="forbid", frozen=True)

    base: dict[str, Any] | str = Field(
        default_factory=dict, description="A run configuration, or the path of a run configuration file."
    )
    grid: dict[str, list[Any]] = Field(description="Dotted setting path -> the values to try.")
    output: str | None = Field(default=None, description="The sweep folder; default: runs/sweep-<axes>.")

    @field_validator("grid")
    @classmethod
    def _non_empty(cls, grid: dict[str, list[Any]]) -> dict[str, list[Any]]:
        if not grid:
            raise ValueError("a sweep needs at least one axis: grid: {path: [values, ...]}")
        for path, values in grid.items():
            if not values:
                raise ValueError(f"axis '{path}' has no values")
        return grid


def value_label(value: Any) -> Any:
    """How a grid value appears in reports and plots: a model configuration by its model's name,
    numbers as numbers, anything else as text.
    """
    if isinstance(value, Mapping):
        if "model" in value:
            return str(value["model"])
        return json.dumps(value, sort_keys=True)
    if isinstance(value, bool | int | float) or value is None:
        return value
    return str(value)


def axis_name(path: str) -> str:
    """The short name of an axis: its last path segment (``models.assistant`` -> ``assistant``)."""
    return path.rsplit(".", 1)[-1]


@dataclass(frozen=True)
class SweepPoint:
    """One combination of the grid's values."""

    values: dict[str, Any]
    """Dotted path -> the value to set."""

    @property
    def params(self) -> dict[str, Any]:
        """Dotted path -> the value's label (what reports and plots show)."""
        return {path: value_label(value) for path, value in self.values.items()}

    def folder(self) -> str:
        """The sub-folder name: ``axis=value`` pairs."""
        return slug("__".join(f"{axis_name(path)}={label}" for path, label in self.params.items()))


def load_sweep(
    path: Path | None,
    *,
    grid: Sequence[tuple[str, list[Any]]] = (),
    base_overrides: Sequence[tuple[str, Any]] = (),
    output: str | None = None,
) -> tuple[SweepSpec, dict[str, Any]]:
    """The sweep from a file (if any) plus command-line axes; returns it and the resolved base mapping."""
    data: dict[str, Any] = read_config_file(path) if path is not None else {}
    merged_grid = dict(data.get("grid") or {})
    for axis, values in grid:
        merged_grid[axis] = values
    data = {**data, "grid": merged_grid}
    if output is not None:
        data["output"] = output
    try:
        spec = SweepSpec.model_validate(data)
    except ValidationError as error:
        where = str(path) if path is not None else "the command line"
        problems = "\n".join(
            f"  {'.'.join(str(p) for p in problem['loc']) or '(top level)'}: {problem['msg']}"
            for problem in error.errors()
        )
        raise UserInputError(f"{where} is not a valid sweep:\n{problems}") from None
    base = spec.base
    if isinstance(base, str):
        base_file = Path(base)
        if path is not None and not base_file.is_absolute():
            base_file = path.parent / base_file
        base = read_config_file(base_file)
    resolved = dict(base)
    for dotted, value in base_overrides:
        resolved = _with(resolved, dotted, value)
    return spec, resolved


def _with(data: dict[str, Any], dotted: str, value: Any) -> dict[str, Any]:
    changed = copy.deepcopy(data)
    set_path(changed, dotted, value)
    return changed


def points(spec: SweepSpec) -> list[SweepPoint]:
    """Every combination of the grid's values, in the grid's order."""
    axes = list(spec.grid)
    return [
        SweepPoint(dict(zip(axes, combination, strict=True)))
        for combination in itertools.product(*spec.grid.values())
    ]


def sweep_folder(spec: SweepSpec) -> Path:
    """Where the sweep's runs go."""
    if spec.output:
        return Path(spec.output)
    return Path("runs") / slug("sweep-" + "-".join(axis_name(path) for path in spec.grid))


def point_configs(spec: SweepSpec, base: Mapping[str, Any]) -> list[tuple[SweepPoint, RunConfig]]:
    """The run configuration of every point (all validated before anything runs)."""
    root = sweep_folder(spec)
    configs: list[tuple[SweepPoint, RunConfig]] = []
    problems: list[str] = []
    for point in points(spec):
        where = ", ".join(f"{axis_name(path)}={label}" for path, label in point.params.items())
        name = f"{base['name']} [{where}]" if base.get("name") else where
        overrides = [*point.values.items(), ("output", str(root / point.folder())), ("name", name)]
        try:
            configs.append(
                (point, build_config(dict(base), overrides=overrides, source=f"sweep point {point.folder()}"))
            )
        except UserInputError as error:
            problems.append(str(error))
    if problems:
        raise UserInputError("\n".join(problems))
    return configs


def run_sweep(
    spec: SweepSpec,
    base: Mapping[str, Any],
    *,
    progress: Callable[[], ProgressSink] | None = None,
) -> list[RunSummary]:
    """Run (or resume) every point of the sweep, one after the other (``progress`` makes each point's
    progress display).
    """
    configs = point_configs(spec, base)
    root = sweep_folder(spec)
    make_output_folder(root, "the sweep folder")
    description = {
        "grid": {path: [value_label(v) for v in values] for path, values in spec.grid.items()},
        "points": [{"folder": point.folder(), "params": point.params} for point, _ in configs],
    }
    (root / SWEEP_FILE).write_text(json.dumps(description, indent=2) + "\n", encoding="utf-8")
    summaries = []
    for point, config in configs:
        sink = progress() if progress is not None else None
        summaries.append(run_benchmark(config, progress=sink, sweep_point=point.params))
    return summaries
