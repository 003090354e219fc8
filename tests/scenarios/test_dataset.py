"""``pare export scenarios``: the library as a dataset with its card, loaded back."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import pytest
import yaml

from pare.cli import main
from pare.scenarios.library import library, splits
from pare.scenarios.loader import parse_scenario


def _card(folder: Path) -> dict[str, Any]:
    text = (folder / "README.md").read_text(encoding="utf-8")
    assert text.startswith("---\n")
    front, _, _ = text[4:].partition("\n---\n")
    header: dict[str, Any] = yaml.safe_load(front)
    return header


def _rows(folder: Path, path: str) -> list[dict[str, Any]]:
    try:
        import datasets  # type: ignore[import-not-found]
    except ImportError:  # the test tools do not include it: read the file as it would
        return [json.loads(line) for line in (folder / path).read_text(encoding="utf-8").splitlines()]
    return list(datasets.load_dataset(str(folder), split="train", cache_dir=str(folder.parent / "hf-cache")))


def test_the_library_exports_as_json_lines_with_a_card_and_reads_back(tmp_path: Path) -> None:
    out = tmp_path / "dataset"
    assert main(["export", "scenarios", "-o", str(out)]) == 0
    card = _card(out)
    (data_file,) = card["configs"][0]["data_files"]
    rows = _rows(out, data_file["path"])
    scenarios = library()
    assert sorted(row["id"] for row in rows) == sorted(scenarios)
    smoke = set(splits()["smoke"])
    for row in rows:
        scenario = scenarios[row["id"]]
        assert row["content_hash"] == scenario.content_hash()
        assert parse_scenario(row["scenario"]).content_hash() == scenario.content_hash()
        assert [goal["description"] for goal in row["goals"]] == [goal.description for goal in scenario.goals]
        assert ("smoke" in row["splits"]) == (row["id"] in smoke)


def test_a_split_exports_as_parquet(tmp_path: Path) -> None:
    pq = pytest.importorskip("pyarrow.parquet")
    out = tmp_path / "smoke"
    assert main(["export", "scenarios", "--split", "smoke", "--format", "parquet", "-o", str(out)]) == 0
    (data_file,) = _card(out)["configs"][0]["data_files"]
    table = pq.read_table(out / data_file["path"])
    assert sorted(table.column("id").to_pylist()) == sorted(splits()["smoke"])


@pytest.mark.parametrize("data_format", ["jsonl", "parquet"])
def test_hugging_face_datasets_loads_both_formats(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, data_format: str
) -> None:
    datasets = pytest.importorskip(
        "datasets", reason="the hf extra is not installed (pip install -e '.[hf]')"
    )
    if data_format == "parquet":
        pytest.importorskip("pyarrow", reason="the parquet extra is not installed")
    monkeypatch.setenv("HF_HUB_OFFLINE", "1")  # a local file: nothing to fetch
    out = tmp_path / "smoke"
    assert main(["export", "scenarios", "--split", "smoke", "--format", data_format, "-o", str(out)]) == 0
    (data_file,) = _card(out)["configs"][0]["data_files"]
    builder = "json" if data_format == "jsonl" else "parquet"
    loaded = datasets.load_dataset(
        builder, data_files=str(out / data_file["path"]), split="train", cache_dir=str(tmp_path / "cache")
    )
    smoke = splits()["smoke"]
    assert loaded.num_rows == len(smoke)
    assert sorted(loaded["id"]) == sorted(smoke)
    scenarios = library()
    for row in loaded:
        assert row["content_hash"] == scenarios[row["id"]].content_hash()
        assert parse_scenario(row["scenario"]).content_hash() == row["content_hash"]


def test_an_unknown_dataset_format_is_refused(tmp_path: Path, capsys) -> None:
    assert main(["export", "scenarios", "--format", "csv", "-o", str(tmp_path / "x")]) == 2
    assert "jsonl or parquet" in capsys.readouterr().err
