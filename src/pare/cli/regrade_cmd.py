"""``pare regrade``: a run's stored trajectories judged again with today's checks, into a new folder."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from pare.cli.run_cmd import JudgeEndpoint, JudgeModel, JudgeProvider, load_config, role_models

SHOWN = 10
"""How many changed verdicts the summary lists before it says how many more there are."""


def regrade(
    run: Annotated[Path, typer.Argument(help="The run folder to re-grade.", show_default=False)],
    output: Annotated[
        Path | None,
        typer.Option("--output", "-o", help="The new run folder (default: RUN-regraded beside it)."),
    ] = None,
    judge_model: JudgeModel = None,
    judge_provider: JudgeProvider = None,
    judge_endpoint: JudgeEndpoint = None,
    deterministic_judge: Annotated[
        bool,
        typer.Option(
            "--deterministic-judge", help="Read free-text checks by their fallbacks, not the run's judge."
        ),
    ] = False,
    scenario_path: Annotated[
        list[str] | None,
        typer.Option(
            "--scenario-path", help="Scenario files or folders to judge by (default: what the run used)."
        ),
    ] = None,
) -> None:
    """Judge a run's stored episodes again with today's checks (no model is called but the judge).

    The new folder names the original run and both versions of each scenario; each record keeps its old
    verdict, and `pare view` shows what changed. Scores before and after are not comparable: `pare report`
    puts the two runs in one table only with --allow-mixed.
    """
    from pare.bench.regrade import default_output, regrade_run
    from pare.terminal_text import make_console, markup_safe, plain_text

    judge = None
    if judge_model is not None:
        overrides = [
            (f"models.judge.{name}", value)
            for name, value in role_models(judge=(judge_model, judge_provider, judge_endpoint))[
                "judge"
            ].items()
            if value is not None
        ]
        judge = load_config(None, overrides).models.judge
    target = output or default_output(run)
    summary = regrade_run(
        run, target, judge=judge, keep_judge=not deterministic_judge, scenario_paths=scenario_path
    )
    console = make_console()
    who = f"judge {summary.judge}" if summary.judge else "the checks' deterministic fallbacks"
    console.print(
        plain_text(
            f"{summary.regraded} episodes re-graded with today's checks ({who}); "
            f"{len(summary.changed)} verdicts changed; {summary.carried} carried over as they were "
            "(failed or missing in the original)"
        )
    )
    for changed in summary.changed[:SHOWN]:
        goals = ", ".join(
            f"{goal} {'pass' if was else 'fail'} -> {'pass' if now else 'fail'}"
            for goal, (was, now) in sorted(changed.goals.items())
        )
        verdict = f"{'success' if changed.was else 'failure'} -> {'success' if changed.now else 'failure'}"
        console.print(plain_text(f"  {changed.scenario_id} run {changed.run}: {verdict} ({goals})"))
    if len(summary.changed) > SHOWN:
        console.print(f"  and {len(summary.changed) - SHOWN} more")
    for scenario_id, run_index, why in summary.refused:
        console.print(
            f"[yellow]not re-graded[/yellow]: {markup_safe(scenario_id)} run {run_index}: {markup_safe(why)}"
        )
    where = markup_safe(summary.path)
    console.print(f"results: {where}   what changed: pare view {where}")
