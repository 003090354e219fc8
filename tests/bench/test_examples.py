"""The examples in examples/ stay valid: the configurations load, the scripts run."""

from __future__ import annotations

import importlib
import sys
from pathlib import Path

import pytest

from pare.bench.runconfig import build_config, read_config_file
from pare.bench.runner import select_scenarios
from pare.bench.sweep import load_sweep, point_configs
from pare.cli import main as pare
from pare.results.run_folder import load_run

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


@pytest.mark.parametrize("path", sorted(EXAMPLES.glob("run-*.yaml")), ids=lambda p: p.name)
def test_run_examples_are_valid(path: Path) -> None:
    config = build_config(read_config_file(path), source=str(path))
    assert not config.oracle_only


@pytest.mark.parametrize("path", sorted(EXAMPLES.glob("sweep-*.yaml")), ids=lambda p: p.name)
def test_sweep_examples_are_valid(path: Path) -> None:
    spec, base = load_sweep(path)
    configs = point_configs(spec, base)
    assert len(configs) > 1
    assert len({config.identity_hash() for _, config in configs}) == len(configs)


def test_the_offline_rehearsal_runs_the_model_path_with_no_key(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    for variable in ("OPENAI_API_KEY", "ANTHROPIC_API_KEY"):
        monkeypatch.delenv(variable, raising=False)
    monkeypatch.setenv("COLUMNS", "200")
    monkeypatch.syspath_prepend(str(EXAMPLES))
    rehearsal = importlib.import_module("offline_rehearsal")

    assert rehearsal.main(["--output", str(tmp_path / "run")]) == 0
    out = capsys.readouterr().out
    assert "dry run" in out and "Estimate for the 5 episodes to run" in out
    loaded = load_run(tmp_path / "run")
    assert len(loaded.records) == 5 and all(record.complete for record in loaded.records)
    calls = sum(usage.calls for record in loaded.records for usage in record.usage.values())
    assert calls > 0 and f"the local server answered {calls} model calls" in out
    assert loaded.manifest["judge"]["model"] == "rehearsal-judge"


def test_the_example_assistant_runs_from_its_folder(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    monkeypatch.setattr(sys, "path", [entry for entry in sys.path if entry not in ("", str(EXAMPLES))])
    monkeypatch.chdir(EXAMPLES)  # `pare` looks for the module in the current folder, as the docstring says
    argv = ["run", "--split", "smoke", "--runs", "1", "--no-progress", "--output", str(tmp_path / "run")]
    assert pare([*argv, "--assistant-policy", "my_assistant:make"]) == 0
    loaded = load_run(tmp_path / "run")
    assert loaded.label == "my_assistant:make"
    assert len(loaded.records) == 5 and all(record.complete for record in loaded.records)
    assert all(record.proposals and record.proposals[0].decision == "accept" for record in loaded.records)


def test_the_user_model_ablation_plays_the_ablation_split() -> None:
    spec, base = load_sweep(EXAMPLES / "sweep-user-models.yaml")
    configs = point_configs(spec, base)
    assert {config.scenarios.split for _, config in configs} == {"ablation"}
    assert len(select_scenarios(configs[0][1])) == 50
