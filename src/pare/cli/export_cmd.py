"""``pare export``: runs in the field's formats (Every Eval Ever, chat-format conversations for
fine-tuning), and the scenario library as a dataset (docs/exporting.md).
"""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from pare.errors import UserInputError

RUN_FORMATS = ("eee", "sft", "inspect")
SCENARIO_FORMATS = ("jsonl", "parquet")


def export(
    targets: Annotated[
        list[str],
        typer.Argument(
            help="Run folders or sweep folders; or the word 'scenarios' for the scenario library.",
            show_default=False,
        ),
    ],
    output: Annotated[
        Path, typer.Option("--output", "-o", help="The folder (eee, inspect, scenarios) or file (sft).")
    ],
    form: Annotated[
        str | None,
        typer.Option(
            "--format",
            "-f",
            help="Runs: eee (default), inspect or sft. Scenarios: jsonl (default) or parquet.",
            show_default=False,
        ),
    ] = None,
    split: Annotated[
        str | None, typer.Option("--split", "-s", help="Scenarios: only this split of the library.")
    ] = None,
    organization: Annotated[
        str, typer.Option("--organization", help="eee: who ran the evaluation.")
    ] = "unknown",
    relationship: Annotated[
        str,
        typer.Option(
            "--relationship", help="eee: first_party, third_party, collaborative or other (to the model)."
        ),
    ] = "third_party",
    role: Annotated[
        list[str] | None,
        typer.Option("--role", help="sft: only this role (user, observe, execute); repeatable."),
    ] = None,
    include_failed: Annotated[
        bool, typer.Option("--include-failed", help="sft: failed episodes' conversations too.")
    ] = False,
) -> None:
    """Write runs in the Every Eval Ever schema (--format eee: the metrics with their uncertainty and one
    record per episode), as Inspect logs (--format inspect) or as chat-format JSON lines of the successful
    episodes per role (--format sft); or, with the word 'scenarios', the library as a dataset with a card.
    """
    if targets == ["scenarios"]:
        _export_scenarios(output, form or "jsonl", split)
        return
    if "scenarios" in targets:
        raise UserInputError(
            "'scenarios' exports the library on its own; name run folders in another command"
        )
    chosen = form or "eee"
    if chosen not in RUN_FORMATS:
        raise UserInputError(f"--format {chosen!r}: a run exports as {', '.join(RUN_FORMATS)}")
    from pare.results.run_folder import load_run, run_folders

    runs = [load_run(folder) for folder in run_folders(Path(target) for target in targets)]
    if chosen == "sft":
        from pare.results.exports.sft import ROLES, export_sft

        if output.is_dir():
            raise UserInputError(f"{output} is a folder; --format sft writes one JSON-lines file")
        try:
            output.parent.mkdir(parents=True, exist_ok=True)
        except OSError as error:
            reason = error.strerror or error
            raise UserInputError(f"{output.parent}: cannot make the folder: {reason}") from None
        lines = export_sft(runs, output, roles=tuple(role or ROLES), include_failed=include_failed)
        typer.echo(f"wrote {lines} conversations to {output}")
        return
    if chosen == "inspect":
        from pare.results.exports.inspect_log import export_inspect

        for run in runs:
            log = export_inspect(run, output)
            typer.echo(f"{run.label}: {log.file} ({log.samples} samples)")
        return
    from pare.results.exports.eee import export_eee

    for run in runs:
        files = export_eee(run, output, organization=organization, relationship=relationship)
        typer.echo(f"{run.label}: {files.aggregate} and {files.instances} instances in {files.samples.name}")


def _export_scenarios(output: Path, form: str, split: str | None) -> None:
    if form not in SCENARIO_FORMATS:
        raise UserInputError(f"--format {form!r}: the scenarios export as {' or '.join(SCENARIO_FORMATS)}")
    import pare
    from pare.scenarios.dataset import export_scenarios
    from pare.scenarios.library import library, select, splits

    scenarios = list(library().values())
    if split is not None:
        scenarios = select(scenarios, split=split)
    data = export_scenarios(
        scenarios,
        splits(),
        output,
        form="parquet" if form == "parquet" else "jsonl",
        version=pare.__version__,
    )
    typer.echo(f"wrote {len(scenarios)} scenarios to {data} and the card {output / 'README.md'}")
