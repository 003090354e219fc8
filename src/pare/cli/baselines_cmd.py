"""``pare baselines``: the model-free assistants on a split, into one folder, as the floor of a report."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from pare.cli.run_cmd import (
    ConfigFile,
    JudgeEndpoint,
    JudgeModel,
    JudgeProvider,
    Sets,
    UserEndpoint,
    UserModel,
    UserProvider,
    collect_overrides,
    load_config,
    progress_sink,
    role_models,
)
from pare.errors import UserInputError, did_you_mean

DEFAULT_FOLDER = Path("runs") / "baselines"


def baselines(
    config_file: ConfigFile = None,
    split: Annotated[
        str | None, typer.Option("--split", help="A split of the library (default: all).")
    ] = None,
    kind: Annotated[
        list[str] | None, typer.Option("--kind", help="Only scenarios of this kind (repeatable).")
    ] = None,
    scenario: Annotated[
        list[str] | None, typer.Option("--scenario", "-s", help="Only this scenario (repeatable).")
    ] = None,
    runs: Annotated[int | None, typer.Option("--runs", "-k", help="Runs per scenario (default 4).")] = None,
    seed: Annotated[int | None, typer.Option("--seed", help="Base seed (default 0).")] = None,
    baseline: Annotated[
        list[str] | None,
        typer.Option(
            "--baseline",
            "-b",
            help="Only this baseline (repeatable): silent, generic_offer, propose_only, random.",
        ),
    ] = None,
    user_model: UserModel = None,
    user_provider: UserProvider = None,
    user_endpoint: UserEndpoint = None,
    judge_model: JudgeModel = None,
    judge_provider: JudgeProvider = None,
    judge_endpoint: JudgeEndpoint = None,
    output: Annotated[
        Path, typer.Option("--output", "-o", help="The folder of the baselines' runs (one run each).")
    ] = DEFAULT_FOLDER,
    sets: Sets = None,
    progress: Annotated[bool, typer.Option("--progress/--no-progress", help="Show a progress bar.")] = True,
) -> None:
    """Run the assistants that need no model (the floor of every result) on the chosen scenarios.

    Each baseline is one run (resumable) in its own folder under OUTPUT, with the user (the oracle, or
    --user-model) deciding as in any run; `pare report RUN OUTPUT` then shows a model beside its floor.
    """
    from pare.bench.build import check_policies
    from pare.bench.runner import run_benchmark
    from pare.cli.report_cmd import collect_metrics
    from pare.results.report import render_terminal
    from pare.scenarios.baselines import BASELINES
    from pare.terminal_text import make_console, markup_safe

    chosen = list(dict.fromkeys(baseline or BASELINES))
    for name in chosen:
        if name not in BASELINES:
            raise UserInputError(
                f"no baseline '{name}'.{did_you_mean(name, BASELINES)} Baselines: {', '.join(BASELINES)}"
            )
    models = role_models(
        user=(user_model, user_provider, user_endpoint), judge=(judge_model, judge_provider, judge_endpoint)
    )
    configs = []
    for name in chosen:
        flags = {
            "scenarios.split": split,
            "scenarios.kinds": kind,
            "scenarios.ids": scenario,
            "runs": runs,
            "seed": seed,
            "name": f"baseline: {name}",
            "policies.assistant": name,
            "output": str(output / name),
        }
        config = load_config(config_file, collect_overrides(sets=sets, flags=flags, models=models))
        check_policies(config)
        configs.append(config)
    console = make_console()
    failed = 0
    for name, config in zip(chosen, configs, strict=True):
        console.print(f"[bold]{name}[/bold]: {markup_safe(BASELINES[name].description)}", highlight=False)
        summary = run_benchmark(config, progress=progress_sink(progress))
        failed += len(summary.failed)
    render_terminal(collect_metrics([output / name for name in chosen]), console, sections=("main", "kinds"))
    where = markup_safe(output)
    console.print(f"baselines: {where}   beside a model: pare report RUN {where}")
    if failed:
        raise typer.Exit(1)
