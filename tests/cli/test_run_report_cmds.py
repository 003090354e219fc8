"""`pare sweep`, `pare report` and `pare plot` end to end on offline (oracle) runs."""

from __future__ import annotations

import csv
import io
import json
from pathlib import Path

import pytest

from pare.cli import main
from pare.results.run_folder import SWEEP_FILE, load_run


@pytest.fixture(autouse=True)
def wide(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("COLUMNS", "240")


def _sweep(tmp_path: Path) -> Path:
    spec = tmp_path / "sweep.yaml"
    spec.write_text(
        "base:\n  scenarios: {split: smoke}\n  runs: 2\n"
        "grid:\n  world.tool_failure_probability: [0.0, 0.5]\n"
        f"output: {tmp_path / 'sweep'}\n"
    )
    assert (
        main(["sweep", "-c", str(spec), "--grid", "world.noise_rate_per_minute=[0, 3]", "--no-progress"]) == 0
    )
    return tmp_path / "sweep"


def test_sweep_runs_every_point_into_one_folder(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    folder = _sweep(tmp_path)
    described = json.loads((folder / SWEEP_FILE).read_text())
    assert [p["params"] for p in described["points"]] == [
        {"world.tool_failure_probability": 0.0, "world.noise_rate_per_minute": 0},
        {"world.tool_failure_probability": 0.0, "world.noise_rate_per_minute": 3},
        {"world.tool_failure_probability": 0.5, "world.noise_rate_per_minute": 0},
        {"world.tool_failure_probability": 0.5, "world.noise_rate_per_minute": 3},
    ]
    for point in described["points"]:
        loaded = load_run(folder / point["folder"])
        assert loaded.sweep_point == point["params"]
        assert len(loaded.records) == 10
        world = loaded.manifest["identity"]["world"]
        assert world["tool_failure_probability"] == point["params"]["world.tool_failure_probability"]
    out = capsys.readouterr().out
    assert "tool_failure_probability=0.5, noise_rate_per_minute=3" in out
    # the sweep resumes: nothing to do the second time
    assert (
        main(
            [
                "sweep",
                "-c",
                str(tmp_path / "sweep.yaml"),
                "-g",
                "world.noise_rate_per_minute=[0,3]",
                "--no-progress",
            ]
        )
        == 0
    )
    assert all(len(load_run(folder / p["folder"]).records) == 10 for p in described["points"])


def test_report_formats(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    folder = _sweep(tmp_path)
    capsys.readouterr()
    assert main(["report", str(folder)]) == 0
    terminal = capsys.readouterr().out
    for heading in ("Success@2", "Proposal", "Accept", "Gather", "By app", "By tag"):
        assert heading in terminal

    assert main(["report", str(folder), "--format", "json"]) == 0
    configurations = json.loads(capsys.readouterr().out)["configurations"]
    assert len(configurations) == 4
    clean = configurations[0]
    assert clean["params"] == {"world.tool_failure_probability": 0.0, "world.noise_rate_per_minute": 0}
    assert clean["success_rate"]["mean"] == 1.0 and clean["success_at_k"] == 1.0

    assert main(["report", str(folder), "--format", "csv", "-o", str(tmp_path / "r.csv")]) == 0
    rows = list(csv.DictReader(io.StringIO((tmp_path / "r.csv").read_text())))
    assert len(rows) == 4 and rows[0]["label"] == clean["label"]

    first = json.loads((folder / SWEEP_FILE).read_text())["points"][0]["folder"]
    assert main(["report", str(folder / first), "--format", "markdown", "--section", "decisions"]) == 0
    markdown = capsys.readouterr().out
    header = next(line for line in markdown.splitlines() if "Accept" in line)
    assert header.startswith("|") and "Gather context" in header
    assert "Success@" not in markdown  # only the section asked for

    assert main(["report", str(folder / first), "--format", "latex", "--section", "main"]) == 0
    latex = capsys.readouterr().out
    assert latex.startswith("\\begin{table}") and "\\toprule" in latex and "\\bottomrule" in latex
    assert "100.0\\% $\\pm$ 0.0\\%" in latex  # escaped for LaTeX, like the paper's tables


def test_an_oracle_run_has_no_cost_rather_than_a_zero_cost(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    assert main(["run", "--split", "smoke", "--runs", "1", "-o", str(tmp_path / "run")]) == 0
    progress = capsys.readouterr().err
    assert "cost n/a" in progress and "$0.0000" not in progress
    assert main(["report", str(tmp_path / "run"), "--section", "cost"]) == 0
    table = capsys.readouterr().out
    row = next(line for line in table.splitlines() if "total" in line)
    assert "$0.0000" not in row and row.count("n/a") == 6


def test_report_refuses_what_is_not_a_run(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["report", str(tmp_path)]) == 2
    assert "holds no PARE run" in capsys.readouterr().err
    folder = _sweep(tmp_path)
    assert main(["report", str(folder), "--section", "everything"]) == 2
    assert "everything" in capsys.readouterr().err


def test_plot_draws_the_robustness_figure(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    pytest.importorskip("matplotlib")
    folder = _sweep(tmp_path)
    capsys.readouterr()
    assert (
        main(["plot", str(folder), "--x", "world.tool_failure_probability", "-o", str(tmp_path / "fig")]) == 0
    )
    written = capsys.readouterr().out.split()
    assert sorted(Path(p).suffix for p in written) == [".png", ".svg"]
    assert (tmp_path / "fig" / "robustness.png").read_bytes().startswith(b"\x89PNG")
    assert main(["plot", str(folder), "--x", "world.no_such_setting", "-o", str(tmp_path / "fig")]) == 2
    assert "world.no_such_setting" in capsys.readouterr().err


@pytest.mark.parametrize("columns", [80, 200])
def test_the_main_table_is_never_cut_at_the_consoles_width(
    columns: int, tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setenv("COLUMNS", str(columns))
    folder = tmp_path / "run"
    assert main(["run", "--split", "smoke", "--runs", "1", "--output", str(folder), "--no-progress"]) == 0
    shown_by_run = capsys.readouterr().out
    assert main(["report", str(folder), "--section", "main", "--section", "decisions"]) == 0
    shown_by_report = capsys.readouterr().out
    for shown in (shown_by_run, shown_by_report):
        assert "…" not in shown  # no header or cell cut short
        assert all(len(line) <= columns for line in shown.splitlines())
        headers = ("Success@1", "Success rate ± SE", "Acceptance rate ± SE", "Coverage")
        if columns == 80:  # one block per configuration: each value beside its whole column name
            for header in headers:
                [line] = [line for line in shown.splitlines() if line.strip().startswith(header + " ")]
                assert line.startswith("  ") and line.split(header, 1)[1].strip()
        else:  # a table: the configuration and its values on one row
            [row] = [line for line in shown.splitlines() if line.startswith("│") and "[100.0%" in line]
            assert row.count("│") == 14  # a bar each side of the main table's 13 columns
            assert row.rstrip().endswith("│"), "the table's right edge was cut off"
    assert "Gather context" in shown_by_report


def test_run_by_kind_and_report_by_kind(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    from pare.scenarios.library import library

    no_proposal = sorted(s.id for s in library().values() if s.kind == "no_proposal")
    out = tmp_path / "quiet"
    assert main(["run", "--kind", "no_proposal", "--runs", "1", "-o", str(out), "--no-progress"]) == 0
    loaded = load_run(out)
    assert sorted(record.scenario_id for record in loaded.records) == no_proposal
    assert {record.kind for record in loaded.records} == {"no_proposal"}
    capsys.readouterr()
    assert main(["report", str(out), "--section", "kinds", "--format", "markdown"]) == 0
    report = capsys.readouterr().out
    assert f"| no_proposal | oracle | {len(no_proposal)} | {len(no_proposal)} | 100.0% | 0.0% |" in report
    assert "| proposal |" not in report


def test_run_refuses_an_unknown_kind(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["run", "--kind", "no-proposal", "-o", str(tmp_path / "x"), "--no-progress"]) == 2
    assert "no_proposal" in capsys.readouterr().err
