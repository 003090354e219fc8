"""``pare run`` and ``pare sweep``: run the benchmark for one configuration, or for a grid of them."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any

import typer

from pare.errors import UserInputError

if TYPE_CHECKING:  # the harness is imported by the commands that run: `pare --help` stays fast
    from rich.console import Console

    from pare.bench.runconfig import RunConfig
    from pare.bench.runner import ProgressSink, RunSummary

ROLE_FLAGS = ("user", "assistant", "observe", "execute", "judge")

ConfigFile = Annotated[
    Path | None, typer.Option("--config", "-c", help="A YAML run configuration; flags override it.")
]
Sets = Annotated[
    list[str] | None,
    typer.Option("--set", help="Override any setting by its dotted path: --set protocol.max_turns=20."),
]


def _model_flag(role: str, what: str, help_text: str) -> Any:
    return typer.Option(f"--{role}-{what}", help=help_text, show_default=False)


# The model flags of every role, shared by `pare run` and `pare doctor` (same names, same meaning).
UserModel = Annotated[str | None, _model_flag("user", "model", "The user simulator's model.")]
UserProvider = Annotated[
    str | None, _model_flag("user", "provider", "openai (any OpenAI-compatible server) or litellm.")
]
UserEndpoint = Annotated[str | None, _model_flag("user", "endpoint", "Base URL of its server.")]
AssistantModel = Annotated[
    str | None, _model_flag("assistant", "model", "The assistant's model (observe and execute).")
]
AssistantProvider = Annotated[str | None, _model_flag("assistant", "provider", "openai or litellm.")]
AssistantEndpoint = Annotated[str | None, _model_flag("assistant", "endpoint", "Base URL of its server.")]
ObserveModel = Annotated[str | None, _model_flag("observe", "model", "Observe mode's model.")]
ObserveProvider = Annotated[str | None, _model_flag("observe", "provider", "openai or litellm.")]
ObserveEndpoint = Annotated[str | None, _model_flag("observe", "endpoint", "Base URL.")]
ExecuteModel = Annotated[str | None, _model_flag("execute", "model", "Execute mode's model.")]
ExecuteProvider = Annotated[str | None, _model_flag("execute", "provider", "openai or litellm.")]
ExecuteEndpoint = Annotated[str | None, _model_flag("execute", "endpoint", "Base URL.")]
JudgeModel = Annotated[
    str | None, _model_flag("judge", "model", "Judge of free-text checks (default: the user's model).")
]
JudgeProvider = Annotated[str | None, _model_flag("judge", "provider", "openai or litellm.")]
JudgeEndpoint = Annotated[str | None, _model_flag("judge", "endpoint", "Base URL.")]
UserPolicyName = Annotated[
    str | None,
    typer.Option(
        "--user-policy",
        help="Who plays the user: model, oracle, slow, busy, silent, or your own as MODULE:FACTORY.",
        show_default=False,
    ),
]
AssistantPolicyName = Annotated[
    str | None,
    typer.Option(
        "--assistant-policy",
        help="Who plays the assistant: model, oracle, silent, unrelated, the baselines generic_offer, "
        "propose_only and random, or your own as MODULE:FACTORY "
        "(a function taking a pare.bench.PolicyContext and returning an AssistantPolicy).",
        show_default=False,
    ),
]

ProtocolFlag = Annotated[
    str | None,
    typer.Option(
        "--protocol",
        help="The turn protocol's preset: pare (default) or paper (the paper's, as far as it specifies "
        "it: docs/paper-conformance.md); the protocol flags and settings given override it.",
        show_default=False,
    ),
]
CacheFlag = Annotated[
    str | None, typer.Option("--cache", help="Model-call cache: off, read_write (default), replay.")
]
UserTrustFlag = Annotated[
    str | None,
    typer.Option(
        "--user-trust",
        help="The user's persona of trust: demanding (default), trusting, busy or sceptical "
        "(protocol.user_trust).",
        show_default=False,
    ),
]


def collect_overrides(
    *,
    sets: list[str] | None,
    flags: dict[str, Any],
    models: dict[str, dict[str, str | None]],
) -> list[tuple[str, Any]]:
    """Dotted-path overrides from the explicit flags (unset ones skipped), then every ``--set``."""
    from pare.bench.runconfig import parse_assignment

    overrides: list[tuple[str, Any]] = [
        (path, value) for path, value in flags.items() if value not in (None, [])
    ]
    for role, fields in models.items():
        for name, value in fields.items():
            if value is not None:
                overrides.append((f"models.{role}.{name}", value))
    overrides.extend(parse_assignment(text) for text in sets or [])
    return overrides


def role_models(**roles: tuple[str | None, str | None, str | None]) -> dict[str, dict[str, str | None]]:
    """Each role's ``(--ROLE-model, --ROLE-provider, --ROLE-endpoint)`` as the fields they set."""
    return {
        role: {"model": model, "backend": provider, "api_base": endpoint}
        for role, (model, provider, endpoint) in roles.items()
    }


def load_config(config_file: Path | None, overrides: list[tuple[str, Any]]) -> RunConfig:
    """The run configuration: the file (if any) with the overrides applied."""
    from pare.bench.runconfig import build_config, read_config_file

    data = read_config_file(config_file) if config_file is not None else {}
    source = str(config_file) if config_file is not None else "the command line"
    return build_config(data, overrides=overrides, source=source)


def progress_sink(show: bool) -> ProgressSink:
    """A progress bar, or nothing (then rich's progress module, slow to import, is never loaded)."""
    from pare.bench.runner import NoProgress

    if not show:
        return NoProgress()
    from pare.bench.progress import RichProgress

    return RichProgress()


def print_summary(summary: RunSummary, console: Console) -> None:
    """What the session did, the headline metrics, and where everything is."""
    from pare.bench.throttling import throttling_summary
    from pare.cli.report_cmd import collect_metrics
    from pare.results.report import render_terminal
    from pare.terminal_text import markup_safe

    console.print(
        f"[bold]{markup_safe(summary.label)}[/bold]: {summary.complete} episodes run in "
        f"{summary.seconds:.1f} s"
        + (f", {summary.skipped} already recorded" if summary.skipped else "")
        + (f", [red]{len(summary.failed)} failed (missing coverage)[/red]" if summary.failed else "")
    )
    for line in throttling_summary(summary.throttling, summary.seconds):
        console.print(f"[yellow]{line}[/yellow]", highlight=False)
    metrics = collect_metrics([summary.path])
    total = metrics[0].usage.get("total") if metrics else None
    used_models = total is not None and total.calls > 0
    render_terminal(
        metrics, console, sections=("main", "cost", "coverage") if used_models else ("main", "coverage")
    )
    where = markup_safe(summary.path)
    console.print(f"results: {where}   full report: pare report {where}")


def run(
    config_file: ConfigFile = None,
    scenario: Annotated[
        list[str] | None, typer.Option("--scenario", "-s", help="A scenario id (repeatable).")
    ] = None,
    split: Annotated[
        str | None, typer.Option("--split", help="A split of the library, e.g. full, smoke or ablation.")
    ] = None,
    app_filter: Annotated[
        list[str] | None, typer.Option("--app", "-a", help="Only scenarios using this app (repeatable).")
    ] = None,
    tag: Annotated[
        list[str] | None, typer.Option("--tag", "-t", help="Only scenarios with this tag (repeatable).")
    ] = None,
    difficulty: Annotated[
        list[str] | None, typer.Option("--difficulty", help="Only this difficulty (repeatable).")
    ] = None,
    kind: Annotated[
        list[str] | None,
        typer.Option(
            "--kind",
            help="Only scenarios of this kind: proposal (the right move is to propose) or no_proposal "
            "(repeatable).",
        ),
    ] = None,
    scenario_path: Annotated[
        list[str] | None,
        typer.Option(
            "--scenario-path", help="Scenario files or folders instead of the library (repeatable)."
        ),
    ] = None,
    runs: Annotated[int | None, typer.Option("--runs", "-k", help="Runs per scenario (default 4).")] = None,
    seed: Annotated[int | None, typer.Option("--seed", help="Base seed (default 0).")] = None,
    name: Annotated[str | None, typer.Option("--name", help="A label for reports and the folder.")] = None,
    user_model: UserModel = None,
    user_provider: UserProvider = None,
    user_endpoint: UserEndpoint = None,
    assistant_model: AssistantModel = None,
    assistant_provider: AssistantProvider = None,
    assistant_endpoint: AssistantEndpoint = None,
    observe_model: ObserveModel = None,
    observe_provider: ObserveProvider = None,
    observe_endpoint: ObserveEndpoint = None,
    execute_model: ExecuteModel = None,
    execute_provider: ExecuteProvider = None,
    execute_endpoint: ExecuteEndpoint = None,
    judge_model: JudgeModel = None,
    judge_provider: JudgeProvider = None,
    judge_endpoint: JudgeEndpoint = None,
    user_policy: UserPolicyName = None,
    assistant_policy: AssistantPolicyName = None,
    protocol: ProtocolFlag = None,
    user_trust: UserTrustFlag = None,
    max_turns: Annotated[
        int | None, typer.Option("--max-turns", help="Turns per episode (default 10).")
    ] = None,
    user_steps: Annotated[
        int | None, typer.Option("--user-steps", help="User actions per turn (default 1).")
    ] = None,
    observe_steps: Annotated[
        int | None, typer.Option("--observe-steps", help="Assistant actions per observe turn (default 5).")
    ] = None,
    execute_steps: Annotated[
        int | None, typer.Option("--execute-steps", help="Assistant actions per accepted task (default 10).")
    ] = None,
    tool_failure_prob: Annotated[
        float | None,
        typer.Option("--tool-failure-prob", help="Chance an assistant tool call fails (default 0)."),
    ] = None,
    noise_rate: Annotated[
        float | None,
        typer.Option("--noise-rate", help="Distractor notifications per simulated minute (default 0)."),
    ] = None,
    concurrency: Annotated[
        int | None, typer.Option("--concurrency", "-j", help="Episodes at once (default 8).")
    ] = None,
    cache: CacheFlag = None,
    output: Annotated[
        str | None, typer.Option("--output", "-o", help="Run folder (default runs/<label>-<identity>).")
    ] = None,
    backend: Annotated[str | None, typer.Option("--backend", help="local (default) or ray.")] = None,
    ray_address: Annotated[str | None, typer.Option("--ray-address", help="Ray cluster to join.")] = None,
    sets: Sets = None,
    progress: Annotated[bool, typer.Option("--progress/--no-progress", help="Show a progress bar.")] = True,
    dry_run: Annotated[
        bool,
        typer.Option(
            "--dry-run",
            help="Show the roles, API keys, episodes and an estimate of calls, tokens and cost; call no "
            "provider and make no folder.",
        ),
    ] = False,
    output_format: Annotated[
        str, typer.Option("--format", help="With --dry-run: text (default) or json.")
    ] = "text",
) -> None:
    """Run the benchmark (or resume it: finished episodes are kept, the rest are run).

    With no model configured, the scenarios' oracle plays both roles: the whole pipeline, offline.
    """
    from pare.bench.build import check_policies
    from pare.bench.runner import run_benchmark
    from pare.terminal_text import make_console, markup_safe

    if output_format not in ("text", "json"):
        raise UserInputError(f"--format is text or json, not '{output_format}'")
    if output_format != "text" and not dry_run:
        raise UserInputError("--format applies to --dry-run only")

    flags = {
        "scenarios.ids": scenario,
        "scenarios.split": split,
        "scenarios.apps": app_filter,
        "scenarios.tags": tag,
        "scenarios.difficulty": difficulty,
        "scenarios.kinds": kind,
        "scenarios.paths": scenario_path,
        "runs": runs,
        "seed": seed,
        "name": name,
        "policies.user": user_policy,
        "policies.assistant": assistant_policy,
        "protocol.preset": protocol,
        "protocol.user_trust": user_trust,
        "protocol.max_turns": max_turns,
        "protocol.user_steps": user_steps,
        "protocol.observe_steps": observe_steps,
        "protocol.execute_steps": execute_steps,
        "world.tool_failure_probability": tool_failure_prob,
        "world.noise_rate_per_minute": noise_rate,
        "concurrency": concurrency,
        "cache": cache,
        "output": output,
        "backend": backend,
        "ray_address": ray_address,
    }
    models = role_models(
        user=(user_model, user_provider, user_endpoint),
        assistant=(assistant_model, assistant_provider, assistant_endpoint),
        observe=(observe_model, observe_provider, observe_endpoint),
        execute=(execute_model, execute_provider, execute_endpoint),
        judge=(judge_model, judge_provider, judge_endpoint),
    )
    config = load_config(config_file, collect_overrides(sets=sets, flags=flags, models=models))
    check_policies(config)  # a policy that cannot be found is named before anything else is said
    console = make_console()
    if dry_run:
        from pare.cli.dry_run import print_plan

        print_plan(config, console, as_json=output_format == "json")
        return
    if not config.oracle_only:
        print_roles(config, console)
    if config.custom_policies():
        print_policies(config, console)
    if config.scenarios.paths:
        warn_about_broken_oracles(config, console)
    try:
        summary = run_benchmark(config, progress=progress_sink(progress))
    except KeyboardInterrupt:
        console.print(
            f"[yellow]interrupted[/yellow]: every finished episode is recorded in "
            f"{markup_safe(config.output_dir())}; "
            "run the same command again to resume."
        )
        raise typer.Exit(130) from None
    print_summary(summary, console)
    if not config.oracle_only:
        print_judge_note(config, console)
    if summary.failed:
        raise typer.Exit(1)


def print_roles(config: RunConfig, console: Console) -> None:
    """Which model plays each role, said before anything runs (and costs)."""
    from pare.terminal_text import plain_text

    roles = config.models.roles()
    parts = []
    for role in ("user", "observe", "execute"):
        model = roles.get(role)
        parts.append(f"{role} {model.model if model is not None else 'oracle'}")
    judge = config.judge_provenance()
    parts.append(f"judge {judge['model'] or 'deterministic fallbacks'}")
    console.print(plain_text("models: " + ", ".join(parts)), highlight=False)
    print_judge_note(config, console)


def print_policies(config: RunConfig, console: Console) -> None:
    """Who plays each role, said when a role is not played by its model or the oracle as by default."""
    from pare.terminal_text import plain_text

    players = ", ".join(f"{role} {name}" for role, name in config.policy_names().items())
    console.print(plain_text(f"policies: {players}"), highlight=False)


def print_judge_note(config: RunConfig, console: Console) -> None:
    """Say when the judge of free-text checks was not chosen but taken from the user's role."""
    from pare.terminal_text import markup_safe

    judge = config.judge_provenance()
    if judge["inherited_from"] == "user":
        console.print(
            f"[yellow]note[/yellow]: free-text checks are judged by the user's model "
            f"({markup_safe(judge['model'])}), "
            "since no judge was set; choose one with --judge-model (and --judge-provider, --judge-endpoint) "
            "or --set models.deterministic_judge=true.",
            highlight=False,
        )


def warn_about_broken_oracles(config: RunConfig, console: Console) -> None:
    """Scenario files given by path have not been through the library's gate: play each one's oracle
    first, and say which cannot be passed even by their own solution (their success rates would mean
    nothing). The run goes on; ``pare scenarios check`` gives the whole gate.
    """
    from pare.bench.runner import select_scenarios
    from pare.bench.selftest import oracle_breaches
    from pare.terminal_text import plain_text

    for scenario in select_scenarios(config).values():
        breaches = oracle_breaches(scenario)
        if breaches:
            console.print(
                f"[yellow]warning[/yellow]: the oracle of scenario '{scenario.id}' does not pass, so no "
                "assistant can be judged fairly on it; see 'pare scenarios check'.",
                highlight=False,
            )
            for line in breaches[:5]:
                console.print(plain_text(f"  {line}"), highlight=False)


def sweep(
    config_file: Annotated[
        Path | None, typer.Option("--config", "-c", help="A sweep file: base configuration and grid.")
    ] = None,
    grid: Annotated[
        list[str] | None,
        typer.Option(
            "--grid",
            "-g",
            help="An axis: path=[v1, v2, ...] (YAML list), e.g. world.noise_rate_per_minute=[0,2,4,6].",
        ),
    ] = None,
    sets: Sets = None,
    output: Annotated[str | None, typer.Option("--output", "-o", help="The sweep folder.")] = None,
    progress: Annotated[bool, typer.Option("--progress/--no-progress", help="Show progress bars.")] = True,
) -> None:
    """Run a grid of configurations (each point a run folder inside the sweep folder); resumes too."""
    from pare.bench.runconfig import parse_assignment
    from pare.bench.sweep import load_sweep, run_sweep, sweep_folder
    from pare.terminal_text import make_console

    axes: list[tuple[str, list[Any]]] = []
    for text in grid or []:
        path, values = parse_assignment(text)
        if not isinstance(values, list):
            values = [values]
        axes.append((path, values))
    overrides = [parse_assignment(text) for text in sets or []]
    spec, base = load_sweep(config_file, grid=axes, base_overrides=overrides, output=output)
    console = make_console()
    try:
        summaries = run_sweep(spec, base, progress=lambda: progress_sink(progress))
    except KeyboardInterrupt:
        console.print(
            "[yellow]interrupted[/yellow]: every finished episode is recorded; run the same command again "
            "to resume."
        )
        raise typer.Exit(130) from None
    folder = sweep_folder(spec)
    _print_sweep(folder, console)
    if any(summary.failed for summary in summaries):
        raise typer.Exit(1)


def _print_sweep(folder: Path, console: Console) -> None:
    from pare.cli.report_cmd import collect_metrics
    from pare.results.report import render_terminal
    from pare.terminal_text import markup_safe

    render_terminal(collect_metrics([folder]), console, sections=("main", "coverage"))
    where = markup_safe(folder)
    console.print(f"results: {where}   report: pare report {where}   figures: pare plot {where}")
