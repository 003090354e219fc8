"""``pare calibrate``: measure how a user model decides proposals whose right answer is known."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Annotated

import typer

from pare.cli.report_cmd import Format
from pare.cli.run_cmd import (
    CacheFlag,
    ConfigFile,
    ProtocolFlag,
    Sets,
    UserEndpoint,
    UserModel,
    UserPolicyName,
    UserProvider,
    UserTrustFlag,
    collect_overrides,
    load_config,
    role_models,
)
from pare.errors import UserInputError

if TYPE_CHECKING:
    from pare.results.calibration import CalibrationMetrics


def calibrate(
    config_file: ConfigFile = None,
    scenario: Annotated[
        list[str] | None, typer.Option("--scenario", "-s", help="A scenario id (repeatable).")
    ] = None,
    split: Annotated[str | None, typer.Option("--split", help="A split of the library, e.g. smoke.")] = None,
    app_filter: Annotated[
        list[str] | None, typer.Option("--app", "-a", help="Only scenarios using this app (repeatable).")
    ] = None,
    tag: Annotated[
        list[str] | None, typer.Option("--tag", "-t", help="Only scenarios with this tag (repeatable).")
    ] = None,
    case_kind: Annotated[
        list[str] | None,
        typer.Option(
            "--case-kind",
            help="Only cases of this kind (repeatable): oracle, variant, mutant, unrelated, tempting.",
        ),
    ] = None,
    per_scenario: Annotated[
        int | None,
        typer.Option(
            "--per-scenario", help="Variants, mutants and tempting proposals each per scenario (2)."
        ),
    ] = None,
    max_steps: Annotated[
        int | None,
        typer.Option("--max-steps", help="The user's actions on one case, its answer included (default 6)."),
    ] = None,
    user_model: UserModel = None,
    user_provider: UserProvider = None,
    user_endpoint: UserEndpoint = None,
    user_policy: UserPolicyName = None,
    user_trust: UserTrustFlag = None,
    protocol: ProtocolFlag = None,
    concurrency: Annotated[
        int | None, typer.Option("--concurrency", "-j", help="Cases at once (default 8).")
    ] = None,
    cache: CacheFlag = None,
    output: Annotated[
        str | None,
        typer.Option(
            "--output", "-o", help="The calibration folder (default runs/calibrate-<user>-<identity>)."
        ),
    ] = None,
    sets: Sets = None,
    output_format: Annotated[
        Format, typer.Option("--format", "-f", help="How to print the report at the end.")
    ] = Format.terminal,
    progress: Annotated[bool, typer.Option("--progress/--no-progress", help="Show a progress bar.")] = True,
) -> None:
    """Put proposals whose right answer is known to a user (a model, or a built-in user such as
    oracle_strict or accept_all) and report how it decides them: the confusion table, accept-when-wrong and
    reject-when-right rates with Wilson intervals, looking things up first, per case kind, app and tag.
    Resumes like a run; 'pare report' and 'pare plot' read the folder it writes.
    """
    from pare.bench.calibration.cases import CASE_KINDS
    from pare.bench.calibration.run import CalibrationSettings, run_calibration
    from pare.terminal_text import make_console, markup_safe

    flags = {
        "scenarios.ids": scenario,
        "scenarios.split": split,
        "scenarios.apps": app_filter,
        "scenarios.tags": tag,
        "policies.user": user_policy,
        "protocol.preset": protocol,
        "protocol.user_trust": user_trust,
        "concurrency": concurrency,
        "cache": cache,
        "output": output,
    }
    models = role_models(user=(user_model, user_provider, user_endpoint))
    config = load_config(config_file, collect_overrides(sets=sets, flags=flags, models=models))
    kinds = tuple(case_kind or CASE_KINDS)
    settings = CalibrationSettings(
        kinds=kinds,  # type: ignore[arg-type]  # checked by CalibrationSettings, with the kinds named
        **({"per_scenario": per_scenario} if per_scenario is not None else {}),
        **({"max_steps": max_steps} if max_steps is not None else {}),
    )
    console = make_console(stderr=True)
    if config.policy("user") == "oracle":
        console.print(
            "[yellow]note[/yellow]: no user model or policy was given, so the oracle user is calibrated, "
            "and it accepts every proposal; give --user-model, or --user-policy oracle_strict for the "
            "reference.",
            highlight=False,
        )
    try:
        if progress:
            from rich.progress import Progress

            with Progress(console=console, transient=True) as bar:
                task = bar.add_task("calibrating", total=None)

                def advance(record: object, done: int, total: int) -> None:
                    bar.update(task, completed=done, total=total)

                summary = run_calibration(config, settings, on_case=advance)
        else:
            summary = run_calibration(config, settings)
    except KeyboardInterrupt:
        console.print(
            "[yellow]interrupted[/yellow]: every finished case is recorded; run the same command again."
        )
        raise typer.Exit(130) from None
    where = markup_safe(summary.path)
    console.print(
        f"[bold]{markup_safe(summary.label)}[/bold]: {summary.played} cases played in {summary.seconds:.1f} s"
        + (f", {summary.skipped} already recorded" if summary.skipped else "")
        + (f", [red]{len(summary.failed)} failed[/red]" if summary.failed else ""),
        highlight=False,
    )
    print_calibrations([summary.path], output_format)
    console.print(
        f"results: {where}   again: pare report {where}   figure: pare plot {where}", highlight=False
    )
    if summary.failed:
        raise typer.Exit(1)


def calibration_metrics_of(paths: list[Path]) -> list[CalibrationMetrics]:
    """The measures of each calibration folder in ``paths``."""
    from pare.results.calibration import calibration_metrics, load_calibration

    return [calibration_metrics(load_calibration(path)) for path in paths]


def print_calibrations(paths: list[Path], output_format: Format, output: Path | None = None) -> None:
    """Print (or write to ``output``) the report of the calibration folders ``paths`` in ``output_format``."""
    import io

    from pare.output_paths import write_output_file
    from pare.results import calibration_report as render
    from pare.terminal_text import make_console, printable, printable_json

    metrics = calibration_metrics_of(paths)
    if output_format is Format.terminal:
        if output is None:
            render.render_terminal(metrics, make_console())
            return
        buffer = io.StringIO()
        render.render_terminal(metrics, make_console(file=buffer, width=200))
        write_output_file(output, buffer.getvalue(), "--output")
        return
    renderers = {
        Format.markdown: render.render_markdown,
        Format.latex: render.render_latex,
        Format.csv: render.render_csv,
        Format.json: render.render_json,
    }
    text = renderers[output_format](metrics)
    if output is not None:
        write_output_file(output, text, "--output")
    else:
        shown = printable_json(text) if output_format is Format.json else printable(text)
        typer.echo(shown, nl=not text.endswith("\n"))


def calibration_folders(paths: list[Path]) -> list[Path] | None:
    """``paths`` when every one is a calibration folder, ``None`` when none is.

    Raises:
        UserInputError: Some are calibrations and some are not: they are reported apart.
    """
    from pare.results.calibration import is_calibration

    found = [is_calibration(path) for path in paths]
    if all(found):
        return list(paths)
    if any(found):
        raise UserInputError(
            "calibration folders and run folders cannot share one report; give them to 'pare report' apart"
        )
    return None
