"""The robustness figure: files written, deterministic, clear errors."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

from pare.errors import UserInputError
from pare.results.metrics import ConfigurationMetrics, compute_metrics
from pare.results.plots import _lines, axis_label, plot_sweep
from tests.results.test_metrics import record

NOISE = "env.noise_rate_per_minute"


def point(model: str, noise: float, successes: int) -> ConfigurationMetrics:
    """Two scenarios x two runs; the first ``successes`` episodes succeed."""
    keys = [(s, r) for s in "AB" for r in (1, 2)]
    records = [
        record(s, r, success=i < successes, proposals=(("accept", "accepted"),) if i % 2 else ())
        for i, (s, r) in enumerate(keys)
    ]
    return compute_metrics(
        records, label=f"{model}@{noise}", runs=2, planned=keys, params={NOISE: noise, "assistant": model}
    )


@pytest.fixture(scope="module")
def sweep() -> list[ConfigurationMetrics]:
    # given out of x order: the plot sorts points by x
    return [
        point(model, noise, wins)
        for model in ("big", "small")
        for noise, wins in ((6.0, 1), (2.0, 4), (4.0, 2))
    ]


def test_png_and_svg_written(tmp_path: Path, sweep: list[ConfigurationMetrics]) -> None:
    paths = plot_sweep(sweep, x=NOISE, group_by="assistant", out_dir=tmp_path / "figs", title="Noise")
    assert paths == [tmp_path / "figs" / "robustness.png", tmp_path / "figs" / "robustness.svg"]
    assert paths[0].read_bytes().startswith(b"\x89PNG\r\n\x1a\n")
    svg = paths[1].read_text()
    assert svg.lstrip().startswith("<?xml") and "<svg" in svg


def test_renders_are_byte_identical(tmp_path: Path, sweep: list[ConfigurationMetrics]) -> None:
    first = plot_sweep(sweep, x=NOISE, group_by="assistant", out_dir=tmp_path / "a", stem="noise")
    second = plot_sweep(sweep, x=NOISE, group_by="assistant", out_dir=tmp_path / "b", stem="noise")
    assert first[1].read_bytes() == second[1].read_bytes()
    assert first[0].read_bytes() == second[0].read_bytes()


def test_group_by_none_uses_other_params(tmp_path: Path, sweep: list[ConfigurationMetrics]) -> None:
    assert list(_lines(sweep, x=NOISE, group_by=None)) == ["assistant=big", "assistant=small"]
    xs = [x for x, _ in _lines(sweep, x=NOISE, group_by="assistant")["big"]]
    assert xs == [2.0, 4.0, 6.0]
    paths = plot_sweep(sweep, x=NOISE, group_by=None, out_dir=tmp_path)
    assert all(path.exists() for path in paths)


def test_single_line_without_other_params(tmp_path: Path) -> None:
    metrics = [
        compute_metrics(
            [record("A", 1, success=True)], label=str(p), runs=1, planned=[("A", 1)], params={"p": p}
        )
        for p in (0.1, 0.2)
    ]
    paths = plot_sweep(metrics, x="p", group_by=None, out_dir=tmp_path)
    assert all(path.exists() for path in paths)


def test_missing_param(tmp_path: Path, sweep: list[ConfigurationMetrics]) -> None:
    with pytest.raises(UserInputError, match=r"env\.tool_failure_probability"):
        plot_sweep(sweep, x="env.tool_failure_probability", group_by="assistant", out_dir=tmp_path)
    with pytest.raises(UserInputError, match="'user'"):
        plot_sweep(sweep, x=NOISE, group_by="user", out_dir=tmp_path)


def test_non_numeric_x(tmp_path: Path, sweep: list[ConfigurationMetrics]) -> None:
    with pytest.raises(UserInputError, match="must be a number"):
        plot_sweep(sweep, x="assistant", group_by=None, out_dir=tmp_path)


def test_duplicate_point(tmp_path: Path, sweep: list[ConfigurationMetrics]) -> None:
    with pytest.raises(UserInputError, match="share"):
        plot_sweep([*sweep, sweep[0]], x=NOISE, group_by="assistant", out_dir=tmp_path)


def test_missing_matplotlib(
    tmp_path: Path, sweep: list[ConfigurationMetrics], monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setitem(sys.modules, "matplotlib", None)
    with pytest.raises(UserInputError, match=r"pip install .*\[plots\]"):
        plot_sweep(sweep, x=NOISE, group_by="assistant", out_dir=tmp_path)


def test_axis_labels() -> None:
    assert axis_label("env.tool_failure_probability") == "Tool failure probability"
    assert axis_label("noise_rate_per_minute") == "Noise events per minute"
    assert axis_label("env.user_steps_per_turn") == "User steps per turn"
