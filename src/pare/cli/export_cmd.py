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
INSPECT_REFUSAL = (
    "--format inspect is not offered: an Inspect log (EvalLog) is a model of Inspect's own task, solver "
    "and scorer records that only inspect_ai can write and check, and PARE does not depend on it. Export "
    "--format eee instead (Every Eval Ever converts Inspect logs to the same schema), see docs/exporting.md"
)


def export(
    targets: Annotated[
        list[str],
        typer.Argument(
            help="Run folders or sweep folders; or the word 'scenarios' for the scenario library.",
            show_default=False,
        ),
    ],
    output: Annotated[
        Path, typer.Option("--output", "-o", help="The folder (eee, scenarios) or file (sft) to write.")
    ],
    form: Annotated[
        str | None,
        typer.Option(
            "--format",
            "-f",
            help="Runs: eee (default) or sft. Scenarios: jsonl (default) or parquet.",
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
    record per episode) or as chat-format JSON lines of the successful episodes per role (--format sft);
    or, with the word 'scenarios', the scenario library as a dataset with its card.
    """
    if targets == ["scenarios"]:
        _export_scenarios(output, form or "jsonl", split)
        return
    if "scenarios" in targets:
        raise UserInputError(
            "'scenarios' exports the library on its own; name run folders in another command"
        )
    chosen = form or "eee"
    if chosen == "inspect":
        raise UserInputError(INSPECT_REFUSAL)
    if chosen not in RUN_FORMATS:
        raise UserInputError(f"--format {chosen!r}: a run exports as {', '.join(RUN_FORMATS[:2])}")
    from pare.results.run_folder import load_run, run_folders

    runs = [load_run(folder) for folder in run_folders(Path(target) for target in targets)]
    if chosen == "sft":
        from pare.results.exports.sft import ROLES, export_sft

        if output.is_dir():
            raise UserInputError(f"{output} is a folder; --format sft writes one JSON-lines file")
        output.parent.mkdir(parents=True, exist_ok=True)
        lines = export_sft(runs, output, roles=tuple(role or ROLES), include_failed=include_failed)
        typer.echo(f"wrote {lines} conversations to {output}")
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
