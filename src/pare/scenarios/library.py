"""The PARE-Bench library shipped in the package: scenario files, splits, and selection by filters."""

from __future__ import annotations

import functools
import json
from collections.abc import Iterable, Sequence
from pathlib import Path

from pydantic import BaseModel, ConfigDict, Field, ValidationError

from pare.errors import UserInputError, did_you_mean
from pare.scenarios.loader import ScenarioError, load_scenario
from pare.scenarios.model import Scenario
from pare.yaml_source import YamlSyntaxError, load_yaml, read_text_file

BENCH_DIR = Path(__file__).parent / "bench"
"""Where the library's scenario files live, one ``<id>.yaml`` each."""
SPLITS_FILE = BENCH_DIR / "splits.yaml"
ALL = "*"


class Split(BaseModel):
    """A named set of scenarios."""

    model_config = ConfigDict(extra="forbid", frozen=True)

    description: str
    scenarios: list[str] | str = Field(description="Scenario ids, or '*' for every scenario of the library.")


class SplitsFile(BaseModel):
    """The splits file: split name to split."""

    model_config = ConfigDict(extra="forbid", frozen=True)

    splits: dict[str, Split]


def scenario_files(paths: Iterable[str | Path] | None = None) -> list[Path]:
    """The scenario files under ``paths`` (files or directories; the library when none), sorted."""
    found: list[Path] = []
    for path in [BENCH_DIR] if paths is None else [Path(p) for p in paths]:
        if path.is_dir():
            found.extend(p for p in path.glob("*.yaml") if p.name != SPLITS_FILE.name)
        elif path.name == SPLITS_FILE.name:
            continue  # a glob over the library folder names the splits file too
        elif path.exists():
            found.append(path)
        else:
            raise UserInputError(f"{path}: no such scenario file or directory")
    return sorted(found)


def load_scenarios(paths: Iterable[str | Path] | None = None) -> list[Scenario]:
    """Load every scenario under ``paths``; all broken files are reported together."""
    scenarios: list[Scenario] = []
    errors: list[str] = []
    for file in scenario_files(paths):
        try:
            scenarios.append(load_scenario(file))
        except ScenarioError as error:
            errors.append(str(error))
    if errors:
        raise UserInputError("\n".join(errors))
    seen: dict[str, Scenario] = {}
    for scenario in scenarios:
        if scenario.id in seen:
            raise UserInputError(f"two scenario files have the id '{scenario.id}'")
        seen[scenario.id] = scenario
    return scenarios


@functools.cache
def library() -> dict[str, Scenario]:
    """The shipped library by id (loaded and validated once per process)."""
    return {scenario.id: scenario for scenario in load_scenarios()}


def get_scenario(scenario_id: str) -> Scenario:
    """A library scenario by id, with "did you mean" for unknown ids."""
    scenarios = library()
    if scenario_id not in scenarios:
        raise UserInputError(
            f"no scenario '{scenario_id}' in the library.{did_you_mean(scenario_id, scenarios)}"
        )
    return scenarios[scenario_id]


@functools.cache
def splits() -> dict[str, list[str]]:
    """Split name to the ids it holds; every id is checked against the library."""
    try:
        parsed = SplitsFile.model_validate(load_yaml(read_text_file(SPLITS_FILE)))
    except (OSError, YamlSyntaxError, ValidationError) as error:
        raise UserInputError(f"{SPLITS_FILE}: {error}") from None
    # A scenario's id is its file's name (the loader enforces it): the splits are checked against the
    # files, without loading the library a second time in a process that loaded it by path.
    ids = sorted(file.stem for file in scenario_files())
    known = set(ids)
    resolved: dict[str, list[str]] = {}
    for name, split in parsed.splits.items():
        if split.scenarios == ALL:
            resolved[name] = ids
            continue
        if isinstance(split.scenarios, str):
            raise UserInputError(f"{SPLITS_FILE}: split '{name}': scenarios is a list of ids or '*'")
        unknown = [s for s in split.scenarios if s not in known]
        if unknown:
            raise UserInputError(f"{SPLITS_FILE}: split '{name}' names unknown scenarios {unknown}")
        resolved[name] = list(split.scenarios)
    return resolved


SCENARIO_KINDS = ("proposal", "no_proposal")
"""A scenario's kind: whether the right move is to propose (see ``Scenario.kind``)."""


def select(
    scenarios: Sequence[Scenario],
    *,
    ids: Sequence[str] = (),
    split: str | None = None,
    apps: Sequence[str] = (),
    tags: Sequence[str] = (),
    difficulty: Sequence[str] = (),
    kinds: Sequence[str] = (),
) -> list[Scenario]:
    """The scenarios matching every given filter (an app or tag filter keeps scenarios with any of them;
    ``kinds`` keeps ``proposal`` or ``no_proposal`` scenarios).
    """
    chosen = list(scenarios)
    if ids:
        known = {s.id for s in scenarios}
        for scenario_id in ids:
            if scenario_id not in known:
                raise UserInputError(f"no scenario '{scenario_id}'.{did_you_mean(scenario_id, known)}")
        chosen = [s for s in chosen if s.id in ids]
    if split is not None:
        available = splits()
        if split not in available:
            raise UserInputError(
                f"no split '{split}'.{did_you_mean(split, available)} Splits: {', '.join(available)}"
            )
        members = set(available[split])
        chosen = [s for s in chosen if s.id in members]
    if apps:
        chosen = [s for s in chosen if set(apps) & set(s.all_apps)]
    if tags:
        chosen = [s for s in chosen if set(tags) & set(s.tags)]
    if difficulty:
        chosen = [s for s in chosen if s.difficulty in difficulty]
    if kinds:
        for kind in kinds:
            if kind not in SCENARIO_KINDS:
                raise UserInputError(
                    f"no scenario kind '{kind}'.{did_you_mean(kind, SCENARIO_KINDS)} "
                    f"Kinds: {', '.join(SCENARIO_KINDS)}"
                )
        chosen = [s for s in chosen if s.kind in kinds]
    return chosen


SPLITS_HEADER = (
    '# The library\'s splits. "full" is every scenario; "smoke" is a handful that runs in seconds;\n'
    '# "ablation" is a stratified sample that keeps the library\'s mix (pare scenarios sample).\n'
)


def write_split(name: str, description: str, scenario_ids: Sequence[str], file: Path = SPLITS_FILE) -> None:
    """Add the split ``name`` to the splits file, or replace it; the other splits are kept as they are."""
    try:
        parsed = SplitsFile.model_validate(load_yaml(read_text_file(file)))
    except (OSError, YamlSyntaxError, ValidationError) as error:
        raise UserInputError(f"{file}: {error}") from None
    entries = dict(parsed.splits)
    entries[name] = Split(description=description, scenarios=list(scenario_ids))
    lines = [SPLITS_HEADER.rstrip("\n"), "splits:"]
    for split_name, split in entries.items():
        lines.append(f"  {split_name}:")
        lines.append(f"    description: {json.dumps(split.description, ensure_ascii=False)}")  # valid YAML
        if isinstance(split.scenarios, str):
            lines.append(f'    scenarios: "{split.scenarios}"')
        else:
            lines.append("    scenarios:")
            lines.extend(f"      - {scenario_id}" for scenario_id in split.scenarios)
    file.write_text("\n".join(lines) + "\n", encoding="utf-8")
    splits.cache_clear()
