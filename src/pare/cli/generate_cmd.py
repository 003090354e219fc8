"""``pare generate``: write candidate scenarios with a generator model, judged by the self-test gate.

Heavy imports (the pipeline, the scenario library, the model client) happen inside the command, so
``pare --help`` stays fast.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any

import typer

if TYPE_CHECKING:
    from rich.console import Console

    from pare.generate import GenerationSummary


def _split(values: list[str] | None) -> list[str]:
    """Values given repeated or comma-separated (``--apps email,calendar``)."""
    return [part.strip() for value in values or [] for part in value.split(",") if part.strip()]


def generate(
    apps: Annotated[
        list[str],
        typer.Option("--apps", "-a", help="The apps every candidate uses: email,calendar (or repeated)."),
    ],
    output: Annotated[Path, typer.Option("--output", "-o", help="The folder candidates are written to.")],
    count: Annotated[
        int, typer.Option("--count", "-n", min=1, help="Candidates in the folder (finished ones count).")
    ] = 1,
    tags: Annotated[
        list[str] | None,
        typer.Option("--tags", "-t", help="Capability tags to aim at, cycled over the candidates."),
    ] = None,
    difficulty: Annotated[
        list[str] | None,
        typer.Option("--difficulty", "-d", help="Difficulties allowed, cycled over the candidates."),
    ] = None,
    model: Annotated[
        str, typer.Option("--model", "-m", help="The generator model.", envvar="PARE_GENERATOR_MODEL")
    ] = "gpt-4o",
    provider: Annotated[
        str, typer.Option("--provider", help="openai (any OpenAI-compatible server) or litellm.")
    ] = "openai",
    endpoint: Annotated[
        str | None, typer.Option("--endpoint", help="Base URL of the generator's server.")
    ] = None,
    api_key_env: Annotated[
        str | None,
        typer.Option("--api-key-env", help="Variable holding the key ('none' for a local server)."),
    ] = None,
    temperature: Annotated[
        float | None,
        typer.Option(
            "--temperature",
            min=0.0,
            help="The generator's sampling temperature (default 0.7; not sent to reasoning models, which "
            "accept only their own).",
            show_default=False,
        ),
    ] = None,
    timeout: Annotated[
        float, typer.Option("--timeout", min=1.0, help="Seconds one answer may take (a stage is long).")
    ] = 600.0,
    judge_model: Annotated[
        str | None, typer.Option("--judge-model", help="The uniqueness judge (default: the generator).")
    ] = None,
    judge_endpoint: Annotated[
        str | None, typer.Option("--judge-endpoint", help="Base URL of the judge's server.")
    ] = None,
    retries: Annotated[
        int, typer.Option("--retries", min=0, help="Times a stage's problems go back to the model.")
    ] = 3,
    library: Annotated[
        list[Path] | None,
        typer.Option("--library", help="Scenario files or folders to compare with (default: the library)."),
    ] = None,
    concurrency: Annotated[
        int, typer.Option("--concurrency", "-j", min=1, help="Candidates in flight at once.")
    ] = 4,
    cache: Annotated[
        str, typer.Option("--cache", help="Model-call cache: off, read_write, replay.")
    ] = "read_write",
    sets: Annotated[
        list[str] | None,
        typer.Option("--set", help="Any setting by its dotted path: --set generator.max_tokens=16000."),
    ] = None,
    progress: Annotated[bool, typer.Option("--progress/--no-progress", help="Show a progress bar.")] = True,
) -> None:
    """Generate candidate scenarios with a model, judged by the self-test gate (resumable).

    Four stages (story, seed data, events and oracle, goals and variants), each played through the gate
    with its problems sent back to the model; the story is checked for uniqueness against the library.
    Running the same command again resumes.
    """
    from pare.agents.models.capabilities import is_reasoning_model
    from pare.bench.runconfig import parse_assignment, set_path
    from pare.generate import build_generate_config
    from pare.generate import generate as run_generation
    from pare.generate.progress import RichGenerationProgress
    from pare.terminal_text import make_console, markup_safe

    generator = generator_settings(
        model=model,
        provider=provider,
        endpoint=endpoint,
        api_key_env=api_key_env,
        temperature=temperature,
        timeout=timeout,
    )
    judge: dict[str, Any] | None = None
    if judge_model is not None or judge_endpoint is not None:
        judge = {key: value for key, value in generator.items() if key != "temperature"}
        judge["model"] = judge_model or model
        if not is_reasoning_model(judge["model"]):
            judge["temperature"] = 0.0
        if judge_endpoint is not None:
            judge["api_base"] = judge_endpoint
    data: dict[str, Any] = {
        "apps": _split(apps),
        "tags": _split(tags),
        "difficulty": _split(difficulty),
        "count": count,
        "output": str(output),
        "generator": generator,
        "judge": judge,
        "stage_retries": retries,
        "library": [str(path) for path in library or []],
        "concurrency": concurrency,
        "cache": cache,
    }
    for text in sets or []:
        set_path(data, *parse_assignment(text))
    config = build_generate_config(data)
    console = make_console()
    sink = RichGenerationProgress() if progress else None
    try:
        summary = run_generation(config, progress=sink)
    except KeyboardInterrupt:
        console.print(
            f"[yellow]interrupted[/yellow]: finished candidates are kept in {markup_safe(config.folder)}; "
            "run the same "
            "command again to resume."
        )
        raise typer.Exit(130) from None
    print_summary(summary, console)
    if summary.unfinished:
        raise typer.Exit(1)


def generator_settings(
    *,
    model: str,
    provider: str,
    endpoint: str | None,
    api_key_env: str | None = None,
    temperature: float | None = None,
    timeout: float | None = None,
) -> dict[str, Any]:
    """The generator's model configuration from ``pare generate``'s flags (``pare doctor`` uses it too).

    A chat model writes at the generator's usual temperature unless told otherwise; a reasoning model is
    sent none (it refuses any but its default).
    """
    from pare.agents.models.capabilities import is_reasoning_model
    from pare.generate.config import GENERATOR_TEMPERATURE

    if temperature is None and not is_reasoning_model(model):
        temperature = GENERATOR_TEMPERATURE
    generator: dict[str, Any] = {"model": model, "backend": provider}
    if timeout is not None:
        generator["timeout_s"] = timeout
    if temperature is not None:
        generator["temperature"] = temperature
    if endpoint is not None:
        generator["api_base"] = endpoint
    if api_key_env is not None:
        generator["api_key_env"] = None if api_key_env.lower() in ("none", "null", "") else api_key_env
    elif endpoint is not None:
        generator["api_key_env"] = None  # a local server needs no key unless one is named
    return generator


def print_summary(summary: GenerationSummary, console: Console) -> None:
    """Each candidate of the session with how it ended and why, the cost, and what to do next; what the
    generator wrote (ids, problems) and the providers' words are shown as text (see
    :mod:`pare.terminal_text`).
    """
    from rich.table import Table

    from pare.terminal_text import markup_safe, plain_text

    table = Table(title=f"{len(summary.records)} candidates generated in {summary.seconds:.1f} s")
    for column in ("slot", "outcome", "scenario", "stage", "answers", "cost", "why"):
        table.add_column(column, overflow="fold")
    colours = {"passed": "green", "duplicate": "yellow", "failed": "red"}
    for record in sorted(summary.records, key=lambda r: r.index):
        answers = ", ".join(f"{stage} {n}" for stage, n in record.attempts.items())
        why = record.reason
        if record.problems:
            why += ": " + "; ".join(record.problems[:3]) + (" ..." if len(record.problems) > 3 else "")
        cost = str(record.usage.get("total", {}).get("cost", ""))
        table.add_row(
            plain_text(record.slot),
            f"[{colours[record.status]}]{record.status}[/{colours[record.status]}]",
            plain_text(record.scenario_id or ""),
            plain_text(record.stage or ""),
            plain_text(answers),
            plain_text(cost),
            plain_text(why),
        )
    console.print(table)
    if summary.skipped:
        console.print(f"{summary.skipped} candidate(s) were finished in earlier sessions")
    for slot, reason in summary.unfinished.items():
        console.print(
            f"[red]{markup_safe(slot)} unfinished[/red] (run again to resume): {markup_safe(reason)}",
            highlight=False,
        )
    total = summary.usage.get("total", {})
    console.print(
        f"model calls: {total.get('calls', 0)}, tokens {total.get('total_tokens', 0)}, "
        f"cost {total.get('cost', 'n/a')}"
    )
    passed = summary.count("passed")
    console.print(
        f"{passed} passed, {summary.count('duplicate')} duplicate, {summary.count('failed')} failed; "
        f"candidates in {markup_safe(summary.path)}; review them with: pare scenarios review "
        f"{markup_safe(summary.path)}"
    )
