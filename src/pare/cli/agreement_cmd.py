"""``pare agreement``: how often people's annotations agree with the user simulator and with the judge."""

from __future__ import annotations

import io
from pathlib import Path
from typing import Annotated

import typer

from pare.cli.report_cmd import Format, Runs


def agreement(
    runs: Runs,
    output_format: Annotated[
        Format, typer.Option("--format", "-f", help="How to print the table.")
    ] = Format.terminal,
    output: Annotated[Path | None, typer.Option("--output", "-o", help="Write to this file instead.")] = None,
    samples: Annotated[int, typer.Option("--samples", min=100, help="Bootstrap resamples for kappa.")] = 2000,
    seed: Annotated[int, typer.Option("--seed", help="Seed of the bootstrap.")] = 0,
) -> None:
    """Compare the annotations made in pare view (each run folder's annotations.jsonl) with the user
    simulator's answers to the proposals and the judge's verdicts on the texts it read: per configuration,
    the pairs, the observed agreement and Cohen's kappa with a bootstrap 95% interval.
    """
    from pare.output_paths import write_output_file
    from pare.results import agreement_report
    from pare.results.agreement import agreement_of_run
    from pare.results.run_folder import load_run, run_folders
    from pare.terminal_text import make_console, printable, printable_json

    rows = [
        row
        for folder in run_folders(runs)
        for row in agreement_of_run(load_run(folder), samples=samples, seed=seed)
    ]
    if output_format is Format.terminal:
        if output is None:
            agreement_report.render_terminal(rows, make_console())
            return
        buffer = io.StringIO()
        agreement_report.render_terminal(rows, make_console(file=buffer, width=200))
        text = buffer.getvalue()
    elif output_format is Format.markdown:
        text = agreement_report.render_markdown(rows)
    elif output_format is Format.latex:
        text = agreement_report.render_latex(rows)
    elif output_format is Format.csv:
        text = agreement_report.render_csv(rows)
    else:
        text = agreement_report.render_json(rows)
    if output is not None:
        write_output_file(output, text, "--output")
    else:  # labels come from run folders
        shown = printable_json(text) if output_format is Format.json else printable(text)
        typer.echo(shown, nl=not text.endswith("\n"))
