"""`pare baselines`: the model-free assistants run into one folder that `pare report` reads as a floor."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from pare.cli import main
from pare.results.run_folder import load_run


def test_baselines_run_into_one_folder_and_report_beside_a_model(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "floor"
    assert main(["baselines", "--split", "smoke", "--runs", "1", "-o", str(out), "--no-progress"]) == 0
    for name in ("silent", "generic_offer", "propose_only", "random"):
        loaded = load_run(out / name)
        assert loaded.manifest["policies"]["assistant"] == name
        assert loaded.label == f"baseline: {name}"
        assert len(loaded.records) == 5
    assert "pare report RUN" in capsys.readouterr().out
    oracle = tmp_path / "oracle"
    assert main(["run", "--split", "smoke", "--runs", "1", "-o", str(oracle), "--no-progress"]) == 0
    capsys.readouterr()
    assert main(["report", str(oracle), str(out), "--format", "json"]) == 0
    configurations = json.loads(capsys.readouterr().out)["configurations"]
    rates = {c["label"]: c["success_rate"]["mean"] for c in configurations}
    assert rates["oracle"] == 1.0
    assert set(rates) == {
        "oracle",
        *(f"baseline: {n}" for n in ("silent", "generic_offer", "propose_only", "random")),
    }
    assert all(rate < 1.0 for label, rate in rates.items() if label != "oracle")


def test_an_unknown_baseline_is_named(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["baselines", "-b", "silnet", "-o", str(tmp_path / "x"), "--no-progress"]) == 2
    err = capsys.readouterr().err
    assert "silnet" in err and "silent" in err
    assert not (tmp_path / "x").exists()
