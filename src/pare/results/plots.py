"""The paper's robustness figures (proposal, acceptance and success rate against a swept setting) and the
calibration figure (the share of proposals a user accepted, per case kind).

matplotlib is an optional extra (``pip install "pare-bench[plots]"``); it is imported only when a figure is
drawn, so the rest of PARE works without it.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from pare.errors import UserInputError
from pare.install import install_command
from pare.output_paths import make_output_folder
from pare.results.calibration import CalibrationMetrics
from pare.results.metrics import ConfigurationMetrics, Estimate

__all__ = ["PANELS", "axis_label", "plot_calibration", "plot_sweep"]

PANELS: tuple[tuple[str, str], ...] = (
    ("proposal_rate", "Proposal rate (%)"),
    ("acceptance_rate", "Acceptance rate (%)"),
    ("success_rate", "Success rate (%)"),
)
"""The three panels, left to right: the metric drawn and its axis label."""

_LABELS = {
    "tool_failure_probability": "Tool failure probability",
    "noise_rate_per_minute": "Noise events per minute",
    "max_turns": "Turn limit",
    "proposal_ttl_turns": "Proposal lifetime (turns)",
}


def axis_label(param: str) -> str:
    """A readable axis label for a parameter name.

    Known settings get their own wording (``"env.noise_rate_per_minute"`` -> ``"Noise events per
    minute"``); any other name drops its dotted prefix and reads as words (``"env.user_steps"`` ->
    ``"User steps"``).
    """
    name = param.rsplit(".", 1)[-1]
    if name in _LABELS:
        return _LABELS[name]
    words = name.replace("_", " ").replace("-", " ").strip()
    return words[:1].upper() + words[1:] if words else param


def plot_sweep(
    metrics: Sequence[ConfigurationMetrics],
    *,
    x: str,
    group_by: str | None,
    out_dir: Path,
    stem: str = "robustness",
    title: str | None = None,
) -> list[Path]:
    """Draw proposal, acceptance and success rate (percent) against ``params[x]``, one line per group.

    Each configuration is one point: x is its ``params[x]`` (numeric; points sorted by it), y the mean
    across runs, the error bar its standard error across runs (none when undefined). Lines are the
    values of ``params[group_by]`` (for example the assistant model), in order of first appearance; with
    ``group_by=None`` each distinct combination of the other parameters is a line (one line when there
    are none). A point whose metric could not be computed is left out.

    Args:
        metrics: The sweep's configurations.
        x: The swept parameter, e.g. ``"env.noise_rate_per_minute"``.
        group_by: The parameter that separates lines, or ``None``.
        out_dir: Where to write the figure (created if needed).
        stem: The file name without extension.
        title: A title over the three panels.

    Returns:
        The paths of ``<stem>.png`` (150 dpi) and ``<stem>.svg``; the same metrics give the same bytes.

    Raises:
        UserInputError: When matplotlib is missing, or a configuration lacks ``x`` or ``group_by``, has a
            non-numeric ``x``, or repeats another's point.
    """
    if not metrics:
        raise UserInputError("nothing to plot: no configurations were given")
    lines = _lines(metrics, x=x, group_by=group_by)
    try:
        import matplotlib
        from matplotlib.backends.backend_agg import FigureCanvasAgg
        from matplotlib.figure import Figure
    except ImportError as error:
        raise UserInputError(f"plotting needs matplotlib: {install_command('plots')}") from error

    make_output_folder(out_dir, "the figures' folder")
    png, svg = out_dir / f"{stem}.png", out_dir / f"{stem}.svg"
    # the salt fixes the SVG's element ids, which are otherwise random, so equal inputs give equal files
    with matplotlib.rc_context({"svg.hashsalt": "pare", "svg.fonttype": "path"}):
        figure = Figure(figsize=(15, 4.5), layout="constrained")
        FigureCanvasAgg(figure)  # draw with Agg whatever backend the caller's session uses
        axes = figure.subplots(1, len(PANELS), sharex=True)
        for ax, (metric, ylabel) in zip(axes, PANELS, strict=True):
            for index, (name, points) in enumerate(lines.items()):
                _draw_line(ax, points, metric, name, color=f"C{index % 10}")
            ax.set_xlabel(axis_label(x))
            ax.set_ylabel(ylabel)
            ax.set_title(ylabel.removesuffix(" (%)"))
            ax.grid(True, alpha=0.3)
        if any(name is not None for name in lines):
            axes[-1].legend(title=axis_label(group_by) if group_by else None, loc="best", fontsize="small")
        if title:
            figure.suptitle(title)
        figure.savefig(png, format="png", dpi=150, metadata={"Software": None})
        figure.savefig(svg, format="svg", metadata={"Date": None})
    return [png, svg]


_Point = tuple[float, ConfigurationMetrics]


def _lines(
    metrics: Sequence[ConfigurationMetrics], *, x: str, group_by: str | None
) -> dict[str | None, list[_Point]]:
    """The points of each line, sorted by x, after checking every configuration has what is needed."""
    lines: dict[str | None, list[_Point]] = {}
    for m in metrics:
        if x not in m.params:
            raise UserInputError(
                f"configuration {m.label!r} has no parameter {x!r} to plot against; "
                f"its parameters: {', '.join(sorted(m.params)) or 'none'}"
            )
        value = m.params[x]
        # bool is an int in Python, but True/False is not a point on an axis
        if isinstance(value, bool) or not isinstance(value, int | float) or not math.isfinite(value):
            raise UserInputError(
                f"parameter {x!r} of configuration {m.label!r} is {value!r}: a sweep's x must be a number"
            )
        name = _line_name(m, x=x, group_by=group_by)
        points = lines.setdefault(name, [])
        if any(existing == value for existing, _ in points):
            where = f" in line {name!r}" if name is not None else ""
            raise UserInputError(
                f"two configurations share {x}={value!r}{where}; group them with another parameter (group_by)"
            )
        points.append((float(value), m))
    return {name: sorted(points, key=lambda point: point[0]) for name, points in lines.items()}


def _line_name(m: ConfigurationMetrics, *, x: str, group_by: str | None) -> str | None:
    """The legend entry of the line ``m`` belongs to."""
    if group_by is not None:
        if group_by not in m.params:
            raise UserInputError(f"configuration {m.label!r} has no parameter {group_by!r} to group lines by")
        return _text(m.params[group_by])
    others = {name: value for name, value in sorted(m.params.items()) if name != x}
    if not others:
        return None
    return ", ".join(f"{name}={_text(value)}" for name, value in others.items())


def _text(value: Any) -> str:
    return value if isinstance(value, str) else repr(value)


def _draw_line(ax: Any, points: list[_Point], metric: str, name: str | None, *, color: str) -> None:
    """One line of one panel: markers joined by a line, with standard-error bars where defined."""
    xs: list[float] = []
    ys: list[float] = []
    bars: list[tuple[float, float, float]] = []
    for x_value, m in points:
        estimate: Estimate = getattr(m, metric)
        if estimate.mean is None:
            continue
        xs.append(x_value)
        ys.append(estimate.mean * 100)
        if estimate.se is not None:
            bars.append((x_value, estimate.mean * 100, estimate.se * 100))
    ax.plot(xs, ys, marker="o", color=color, label=name)
    if bars:
        ax.errorbar(
            [b[0] for b in bars],
            [b[1] for b in bars],
            yerr=[b[2] for b in bars],
            fmt="none",
            ecolor=color,
            capsize=3,
        )


def plot_calibration(
    metrics: Sequence[CalibrationMetrics],
    *,
    out_dir: Path,
    stem: str = "calibration",
    title: str | None = None,
) -> list[Path]:
    """Draw, per case kind, the share of proposals each calibrated user accepted (percent, Wilson 95% error
    bars), one bar per user: a well-calibrated user is high on the oracle's proposals and low on the rest.

    Returns:
        The paths of ``<stem>.png`` (150 dpi) and ``<stem>.svg``; the same metrics give the same bytes.

    Raises:
        UserInputError: When matplotlib is missing, or no calibration was given.
    """
    if not metrics:
        raise UserInputError("nothing to plot: no calibrations were given")
    kinds = sorted({row.group for item in metrics for row in item.by_kind}, key=lambda k: (k != "oracle", k))
    try:
        import matplotlib
        from matplotlib.backends.backend_agg import FigureCanvasAgg
        from matplotlib.figure import Figure
    except ImportError as error:
        raise UserInputError(f"plotting needs matplotlib: {install_command('plots')}") from error

    make_output_folder(out_dir, "the figures' folder")
    png, svg = out_dir / f"{stem}.png", out_dir / f"{stem}.svg"
    width = 0.8 / len(metrics)
    with matplotlib.rc_context({"svg.hashsalt": "pare", "svg.fonttype": "path"}):
        figure = Figure(figsize=(max(6.0, 1.6 * len(kinds) + 2), 4.5), layout="constrained")
        FigureCanvasAgg(figure)
        ax = figure.subplots()
        for index, item in enumerate(metrics):
            rows = {row.group: row.accepted for row in item.by_kind}
            xs, heights, below, above = [], [], [], []
            for position, kind in enumerate(kinds):
                rate = rows.get(kind)
                if rate is None or rate.value is None or rate.low is None or rate.high is None:
                    continue
                xs.append(position - 0.4 + width * (index + 0.5))
                heights.append(100 * rate.value)
                below.append(100 * (rate.value - rate.low))
                above.append(100 * (rate.high - rate.value))
            ax.bar(
                xs, heights, width, yerr=[below, above], capsize=3, label=item.label, color=f"C{index % 10}"
            )
        ax.set_xticks(range(len(kinds)), [f"{kind}\n(should {_should(kind)})" for kind in kinds])
        ax.set_ylabel("Proposals accepted (%)")
        ax.set_ylim(0, 105)
        ax.grid(True, axis="y", alpha=0.3)
        ax.legend(title="User", loc="best", fontsize="small")
        if title:
            figure.suptitle(title)
        figure.savefig(png, format="png", dpi=150, metadata={"Software": None})
        figure.savefig(svg, format="svg", metadata={"Date": None})
    return [png, svg]


def _should(kind: str) -> str:
    return "accept" if kind == "oracle" else "reject"
