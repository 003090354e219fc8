"""The scenario library as a dataset: one row per scenario (JSON lines, or Parquet with the ``parquet``
extra) and a dataset card (``README.md`` with the YAML front matter the Hugging Face Hub reads), so it
loads with ``datasets.load_dataset("json" | "parquet", ...)`` or from the folder itself.

Each row has the fields people filter and read by (id, title, story, kind, difficulty, tags, apps, the
user's goal and persona, the goals' descriptions, the splits it is in, its content hash) and the whole
scenario as JSON (``scenario``), which :func:`pare.scenarios.loader.parse_scenario` reads back.
"""

from __future__ import annotations

import json
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any, Literal

import yaml

from pare.errors import UserInputError
from pare.install import install_command
from pare.scenarios.model import Scenario

DatasetFormat = Literal["jsonl", "parquet"]
DATA_FILE = {"jsonl": "data/scenarios.jsonl", "parquet": "data/scenarios.parquet"}
"""Where the rows go, relative to the dataset folder (the card's ``configs`` names it)."""


def scenario_row(scenario: Scenario, splits: Mapping[str, Sequence[str]]) -> dict[str, Any]:
    """One scenario as a dataset row (every value a string, a list of strings or a list of goals)."""
    return {
        "id": scenario.id,
        "title": scenario.title,
        "story": scenario.story,
        "kind": scenario.kind,
        "difficulty": str(scenario.difficulty),
        "tags": [str(tag) for tag in scenario.tags],
        "apps": list(scenario.apps),
        "start": scenario.start.isoformat(),
        "user_goal": scenario.user.goal or "",
        "user_persona": scenario.user.persona or "",
        "goals": [{"id": goal.id, "description": goal.description} for goal in scenario.goals],
        "splits": sorted(name for name, ids in splits.items() if scenario.id in ids),
        "content_hash": scenario.content_hash(),
        "scenario": scenario.model_dump_json(exclude_defaults=True),
    }


def export_scenarios(
    scenarios: Sequence[Scenario],
    splits: Mapping[str, Sequence[str]],
    out: Path,
    *,
    form: DatasetFormat = "jsonl",
    version: str = "",
) -> Path:
    """Write ``scenarios`` as a dataset into the folder ``out`` (rows and card); return the rows' file.

    Raises:
        UserInputError: Parquet without pyarrow installed, or a write refused.
    """
    rows = [scenario_row(scenario, splits) for scenario in sorted(scenarios, key=lambda s: s.id)]
    data = out / DATA_FILE[form]
    try:
        data.parent.mkdir(parents=True, exist_ok=True)
        if form == "parquet":
            _write_parquet(rows, data)
        else:
            text = "".join(json.dumps(row, ensure_ascii=False) + "\n" for row in rows)
            data.write_text(text, encoding="utf-8")
        (out / "README.md").write_text(dataset_card(rows, form, version), encoding="utf-8")
    except OSError as error:
        raise UserInputError(f"{out}: cannot write the dataset: {error.strerror or error}") from None
    return data


def _write_parquet(rows: list[dict[str, Any]], file: Path) -> None:
    try:
        import pyarrow as pa
        import pyarrow.parquet as pq
    except ImportError:
        raise UserInputError(
            f"--format parquet needs pyarrow: {install_command('parquet')}; or use --format jsonl"
        ) from None
    pq.write_table(pa.Table.from_pylist(rows), file)


def dataset_card(rows: Sequence[Mapping[str, Any]], form: DatasetFormat, version: str) -> str:
    """The dataset's ``README.md``: the Hub's YAML front matter, then what the rows hold."""
    kinds = sorted({str(row["kind"]) for row in rows})
    header = {
        "pretty_name": "PARE-Bench scenarios",
        "license": "mit",
        "language": ["en"],
        "task_categories": ["text-generation"],
        "tags": ["agents", "proactive-assistants", "user-simulation", "benchmark"],
        "size_categories": ["n<1K" if len(rows) < 1000 else "1K<n<10K"],
        "configs": [{"config_name": "default", "data_files": [{"split": "train", "path": DATA_FILE[form]}]}],
    }
    front = yaml.safe_dump(header, sort_keys=False, allow_unicode=True)
    made_by = f" by PARE {version}" if version else ""
    return (
        f"---\n{front}---\n\n# PARE-Bench scenarios\n\n"
        f"{len(rows)} scenarios of PARE-Bench (kinds: {', '.join(kinds)}), exported{made_by} with "
        "`pare export scenarios`. Each is a situation on a simulated phone: a story, the apps and their "
        "data, the events that arrive, the user's hidden goal, and goals whose checks judge an episode.\n\n"
        "## Fields\n\n"
        "- `id`, `title`, `story`: the scenario and its situation in a few sentences.\n"
        "- `kind`: `proposal` (the right move is to propose a task) or `no_proposal`.\n"
        "- `difficulty`, `tags`, `apps`: what the scenario exercises.\n"
        "- `start`: when the episode starts (ISO 8601).\n"
        "- `user_goal`, `user_persona`: what the simulated user is told (never the assistant).\n"
        "- `goals`: each goal's id and description (its checks are in `scenario`).\n"
        "- `splits`: the named splits of the library that hold it.\n"
        "- `content_hash`: the hash run folders record for the scenario's version.\n"
        "- `scenario`: the whole scenario as JSON, in PARE's scenario format.\n\n"
        "The one split, `train`, is every row: the library's own splits are in the `splits` field.\n"
    )
