"""The ``pare`` command line: a thin layer over the library.

Each command group lives in its own module; :func:`main` takes an argument list and returns an exit code
so tests can call it, and :func:`run` is the console entry point.
"""

from __future__ import annotations

import sys
from collections.abc import Sequence

import typer

import pare
from pare.cli import (
    agreement_cmd,
    apps_cmd,
    baselines_cmd,
    calibrate_cmd,
    doctor_cmd,
    export_cmd,
    generate_cmd,
    play_cmd,
    regrade_cmd,
    report_cmd,
    run_cmd,
    scenarios_cmd,
    view_cmd,
)
from pare.errors import UserInputError

app = typer.Typer(
    name="pare",
    help="PARE: the Proactive Agent Research Environment.",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
    # Plain help and usage errors, as click writes them: the framework's boxed rich help imports a
    # markdown parser, a syntax highlighter and a traceback renderer it does not use for them, which
    # doubled the time `pare --help` takes. Commands still print with rich.
    rich_markup_mode=None,
)
app.add_typer(apps_cmd.app, name="apps")
app.add_typer(scenarios_cmd.app, name="scenarios")
app.command("run")(run_cmd.run)
app.command("doctor")(doctor_cmd.doctor)
app.command("sweep")(run_cmd.sweep)
app.command("baselines")(baselines_cmd.baselines)
app.command("regrade")(regrade_cmd.regrade)
app.command("calibrate")(calibrate_cmd.calibrate)
app.command("report")(report_cmd.report)
app.command("plot")(report_cmd.plot)
app.command("agreement")(agreement_cmd.agreement)
app.command("view")(view_cmd.view)
app.command("export")(export_cmd.export)
app.command("generate")(generate_cmd.generate)
app.command("play")(play_cmd.play)


@app.command()
def version() -> None:
    """Print PARE's version."""
    typer.echo(pare.__version__)


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line with ``argv`` and return its exit code."""
    from pare.terminal_text import show_warnings_as_text

    show_warnings_as_text()
    try:
        app(args=list(argv) if argv is not None else None, prog_name="pare")
    except SystemExit as done:  # the CLI framework exits with the command's code, usage errors with 2
        return done.code if isinstance(done.code, int) else (0 if done.code is None else 1)
    except UserInputError as error:
        from pare.terminal_text import printable  # the message may quote a file or a model: shown as text

        typer.secho(f"error: {printable(error)}", err=True, fg=typer.colors.RED)
        return 2
    return 0


def run() -> None:
    """Console entry point."""
    code = main()
    from pare.bench.collector import skip_final_collection

    skip_final_collection()  # the process ends now: no last walk over everything still alive
    sys.exit(code)
