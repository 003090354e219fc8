"""``pare report`` and ``pare plot``: the paper's tables and robustness figures from run folders."""

from __future__ import annotations

import io
from enum import StrEnum
from pathlib import Path
from typing import TYPE_CHECKING, Annotated

import typer

from pare.errors import UserInputError
from pare.results.report_sections import SECTIONS

if TYPE_CHECKING:  # metrics and reports are imported by the commands: `pare --help` stays fast
    from pare.results.metrics import ConfigurationMetrics
    from pare.results.run_folder import LoadedRun


class Format(StrEnum):
    """Output formats of ``pare report``."""

    terminal = "terminal"
    markdown = "markdown"
    csv = "csv"
    json = "json"
    latex = "latex"


Runs = Annotated[
    list[Path],
    typer.Argument(
        help="Run folders, or sweep folders (every run inside is one configuration).", show_default=False
    ),
]


def collect_metrics(paths: list[Path]) -> list[ConfigurationMetrics]:
    """The metrics of every configuration in ``paths``, in the order given."""
    from pare.results.run_folder import load_run, run_folders

    return [_metrics_of(load_run(folder)) for folder in run_folders(paths)]


def _metrics_of(loaded: LoadedRun) -> ConfigurationMetrics:
    """One run's metrics, with the protocol it played (for the reports' heading)."""
    from pare.protocols import manifest_protocol
    from pare.results.metrics import compute_metrics

    preset, overrides = manifest_protocol(loaded.manifest)
    metrics = compute_metrics(
        loaded.records,
        label=loaded.label,
        runs=loaded.runs,
        planned=loaded.planned,
        params=loaded.sweep_point,
    )
    return metrics.model_copy(update={"protocol": preset, "protocol_overrides": overrides})


def comparable_metrics(paths: list[Path], *, allow_mixed: bool) -> list[ConfigurationMetrics]:
    """The metrics of every configuration in ``paths``, refused when the runs played different protocol
    presets or different versions of a scenario (then, with ``allow_mixed``, a warning on stderr).
    """
    from pare.results.comparable import comparability_problems
    from pare.results.run_folder import load_run, run_folders

    loaded = [load_run(folder) for folder in run_folders(paths)]
    problems = comparability_problems(loaded)
    if problems and not allow_mixed:
        raise UserInputError(
            "these runs are not comparable: "
            + "; ".join(problems)
            + ". Report them apart, or pass --allow-mixed to put them in one report anyway."
        )
    for problem in problems:
        typer.echo(f"warning: not comparable: {problem}", err=True)
    return [_metrics_of(run) for run in loaded]


def report(
    runs: Runs,
    output_format: Annotated[
        Format, typer.Option("--format", "-f", help="How to print the report.")
    ] = Format.terminal,
    section: Annotated[
        list[str] | None,
        typer.Option("--section", help=f"Only these sections (repeatable): {', '.join(SECTIONS)}."),
    ] = None,
    output: Annotated[Path | None, typer.Option("--output", "-o", help="Write to this file instead.")] = None,
    allow_mixed: Annotated[
        bool,
        typer.Option(
            "--allow-mixed",
            help="Report runs of different protocol presets or scenario versions together (with a warning) "
            "instead of refusing.",
        ),
    ] = False,
) -> None:
    """Print the metrics of one or more runs: Success@k, Success^k, success rate ± SE and CI, proposal and
    acceptance rates, read actions, the decision analysis, cost per role, per-app and per-tag results,
    and coverage, under a heading that names the protocol the runs played. Runs of different protocol
    presets or scenario versions are refused unless ``--allow-mixed`` is given. Calibration folders
    (``pare calibrate``) get their own tables.
    """
    from pare.cli.calibrate_cmd import calibration_folders, print_calibrations
    from pare.output_paths import write_output_file
    from pare.results.report import render_csv, render_json, render_latex, render_markdown, render_terminal
    from pare.terminal_text import make_console, printable, printable_json

    calibrations = calibration_folders(runs)
    if calibrations is not None:  # folders of `pare calibrate`: their own tables
        print_calibrations(calibrations, output_format, output)
        return
    sections = tuple(section or SECTIONS)
    unknown = [name for name in sections if name not in SECTIONS]
    if unknown:
        raise UserInputError(
            f"unknown report section {', '.join(unknown)}; choose from {', '.join(SECTIONS)}"
        )
    metrics = comparable_metrics(runs, allow_mixed=allow_mixed)
    if output_format is Format.terminal:
        if output is not None:
            buffer = io.StringIO()
            render_terminal(metrics, make_console(file=buffer, width=200), sections=sections)
            write_output_file(output, buffer.getvalue(), "--output")
        else:
            render_terminal(metrics, make_console(), sections=sections)
        return
    if output_format is Format.markdown:
        text = render_markdown(metrics, sections=sections)
    elif output_format is Format.latex:
        text = render_latex(metrics, sections=sections)
    elif output_format is Format.csv:
        text = render_csv(metrics)
    else:
        text = render_json(metrics)
    if output is not None:
        write_output_file(output, text, "--output")
    else:  # to the terminal: labels and failure messages come from run folders
        shown = printable_json(text) if output_format is Format.json else printable(text)
        typer.echo(shown, nl=not text.endswith("\n"))


def plot(
    runs: Runs,
    x: Annotated[
        str | None,
        typer.Option(
            "--x", help="The swept setting on the x axis (default: the sweep's first numeric axis)."
        ),
    ] = None,
    group_by: Annotated[
        str | None,
        typer.Option("--group-by", help="One line per value of this setting (default: the other axis)."),
    ] = None,
    output: Annotated[Path | None, typer.Option("--output", "-o", help="Folder for the figures.")] = None,
    stem: Annotated[
        str, typer.Option("--name", help="File name of the figures, without extension.")
    ] = "robustness",
    title: Annotated[str | None, typer.Option("--title", help="The figure's title.")] = None,
) -> None:
    """Draw the paper's robustness figure (proposal, acceptance and success rate against a swept setting,
    one line per model, error bars = SE across runs) as PNG and SVG; for calibration folders, the share of
    proposals each user accepted per case kind. Needs the ``plots`` extra.
    """
    from pare.cli.calibrate_cmd import calibration_folders, calibration_metrics_of
    from pare.results.plots import plot_calibration, plot_sweep
    from pare.results.run_folder import SWEEP_FILE

    calibrations = calibration_folders(runs)
    if calibrations is not None:  # folders of `pare calibrate`: the share accepted per case kind
        written = plot_calibration(
            calibration_metrics_of(calibrations),
            out_dir=output or calibrations[0],
            stem="calibration" if stem == "robustness" else stem,
            title=title,
        )
        for path in written:
            typer.echo(str(path))
        return
    metrics = collect_metrics(runs)
    axes = _numeric_axes(metrics)
    x_axis = x or (axes[0] if axes else None)
    if x_axis is None:
        raise UserInputError("no numeric swept setting found in these runs; name one with --x")
    if group_by is None:
        others = sorted({name for m in metrics for name in m.params} - {x_axis})
        group_by = others[0] if len(others) == 1 else None
    folder = output or (runs[0] if (runs[0] / SWEEP_FILE).exists() else Path("."))
    written = plot_sweep(metrics, x=x_axis, group_by=group_by, out_dir=folder, stem=stem, title=title)
    for path in written:
        typer.echo(str(path))


def _numeric_axes(metrics: list[ConfigurationMetrics]) -> list[str]:
    """Settings that take more than one numeric value across the runs, in order of appearance."""
    values: dict[str, set[float]] = {}
    for item in metrics:
        for name, value in item.params.items():
            if isinstance(value, int | float) and not isinstance(value, bool):
                values.setdefault(name, set()).add(float(value))
    return [name for name, seen in values.items() if len(seen) > 1]
