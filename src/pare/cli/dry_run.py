"""``pare run --dry-run``: what a run would do and roughly what it would cost, printed before it runs."""

from __future__ import annotations

import json
from collections.abc import Callable
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from rich.console import Console

    from pare.bench.plan_estimate import Estimate, KeyStatus, RoleLine, RunPlan, Span
    from pare.bench.runconfig import RunConfig


def print_plan(config: RunConfig, console: Console, *, as_json: bool = False) -> None:
    """Plan the run ``config`` describes (no provider called, no folder made) and print it."""
    from pare.bench.build import check_policies
    from pare.bench.plan_estimate import plan_run
    from pare.bench.runner import select_scenarios
    from pare.terminal_text import markup_safe

    check_policies(config)
    plan = plan_run(config, select_scenarios(config))
    if as_json:
        from pare.terminal_text import printable_json

        console.out(printable_json(json.dumps(plan.to_dict(), indent=2, ensure_ascii=False)), highlight=False)
        return
    console.print(
        f"[bold]dry run[/bold]: no provider is called and no folder is made. Configuration: "
        f"{markup_safe(plan.label)}",
        highlight=False,
    )
    _print_roles(plan.roles, console)
    _print_keys(plan.keys, console)
    _print_episodes(plan, console)
    if plan.estimate is not None:
        _print_estimate(plan.estimate, plan, console)
    else:
        console.print(
            "No role has a model: the scenarios' oracle plays, so nothing is called and nothing costs."
        )


def _print_roles(roles: list[RoleLine], console: Console) -> None:
    from rich.table import Table

    from pare.terminal_text import markup_safe, plain_text

    table = Table(title="Roles", title_justify="left", show_edge=False)
    for column in ("role", "model", "backend", "endpoint", "sends", "note"):
        table.add_column(column, overflow="fold")
    for line in roles:
        if line.model is None:
            who = "deterministic fallbacks" if line.policy == "deterministic" else line.policy
            table.add_row(line.role, plain_text(who), "", "", "", "no model: nothing is called")
            continue
        sends = (
            ", ".join(f"{name}={value}" for name, value in line.sampling.items())
            or "nothing (server defaults)"
        )
        notes = []
        if line.inherited_from == "user" and line.role == "judge":
            notes.append("[yellow]the user's model: not set[/yellow]")
        elif line.inherited_from:
            notes.append(f"from {line.inherited_from}")
        if line.native_tools:
            notes.append("native tools")
        notes.append(f"prices: {markup_safe(line.prices or 'unknown')}")
        if line.policy != "model":
            notes.append(f"played by {markup_safe(line.policy)}: estimated as PARE's own actor")
        cells = (line.model, line.backend, line.endpoint, sends)
        table.add_row(line.role, *(plain_text(cell) for cell in cells), "; ".join(notes))
    console.print(table)
    judge = next(line for line in roles if line.role == "judge")
    if judge.inherited_from == "user":
        console.print(
            f"[yellow]note[/yellow]: free-text checks would be judged by the user's model "
            f"({markup_safe(judge.model)}). "
            "Choose the judge with --judge-model (and --judge-provider, --judge-endpoint), or "
            "--set models.deterministic_judge=true.",
            highlight=False,
        )


def _print_keys(keys: list[KeyStatus], console: Console) -> None:
    from pare.terminal_text import markup_safe

    if not keys:
        return
    console.print("[bold]API keys[/bold] (values are never shown)")
    for status in keys:
        roles = ", ".join(status.roles)
        if status.variable is None:
            state = {True: "[green]found[/green]", False: "[red]missing[/red]", None: "-"}[status.found]
            console.print(f"  {state}  {roles}: {markup_safe(status.note)}", highlight=False)
            continue
        state = "[green]found[/green]" if status.found else "[red]missing[/red]"
        console.print(f"  {markup_safe(status.variable)}: {state} ({roles})", highlight=False)
    missing = [markup_safe(status.variable) for status in keys if status.found is False and status.variable]
    if missing:
        console.print(
            f"  the run would stop at its start until {' and '.join(missing)} "
            f"{'is' if len(missing) == 1 else 'are'} set (export {missing[0]}=...)",
            highlight=False,
        )


def _print_episodes(plan: RunPlan, console: Console) -> None:
    from pare.terminal_text import markup_safe

    count = plan.episodes
    where = f"{markup_safe(count.folder)} ({'exists' if count.folder_exists else 'new'})"
    console.print(
        f"[bold]Episodes[/bold]: {count.scenarios} scenarios x {count.runs} runs = {count.planned}; "
        f"{count.finished} already finished; {count.to_run} to run. Folder: {where}",
        highlight=False,
    )
    if count.refused:
        console.print(f"  [red]refused[/red]: {markup_safe(count.refused)}", highlight=False)


def _print_estimate(estimate: Estimate, plan: RunPlan, console: Console) -> None:
    from rich.table import Table

    from pare.terminal_text import plain_text

    table = Table(
        title=f"Estimate for the {estimate.episodes} episodes to run (typical - upper bound; not a quote)",
        title_justify="left",
        show_edge=False,
    )
    for column in ("role", "model", "calls", "prompt tokens", "completion tokens", "cost (USD)"):
        table.add_column(column, justify="left" if column in ("role", "model") else "right")
    for role in estimate.roles:
        table.add_row(
            role.role,
            plain_text(role.model),
            _span(role.calls, _count),
            _span(role.prompt_tokens, _count),
            _span(role.completion_tokens, _count),
            _span(role.cost_usd, _dollars) if role.cost_usd is not None else "unknown",
        )
    total_cost = estimate.cost_usd
    known = estimate.known_cost_usd
    if total_cost is not None:
        cost_text = _span(total_cost, _dollars)
    elif known is not None:
        cost_text = f"{_span(known, _dollars)} + unknown"
    else:
        cost_text = "unknown"
    table.add_row("total", "", _span(estimate.calls, _count), "", "", cost_text)
    console.print(table)
    notes = [
        f"Typical: each scenario played as its oracle plays it ({estimate.mean_turns:.1f} turns on average), "
        "every prompt rendered as PARE would send it, each answer a short thought and one action.",
        f"Upper bound: every episode runs all {estimate.max_turns} turns (max_turns) at that pace and every "
        "accepted task uses all of execute_steps; answers are max_tokens long where it is set.",
        f"Tokens = characters / {estimate.chars_per_token:g} (measured on PARE's prompts with GPT-4o's "
        "tokenizer; other tokenizers differ).",
        "Not counted: malformed answers sent back (up to max_format_retries a step) and a reasoning model's "
        f"thinking beyond max_tokens. No episode can make more than {estimate.ceiling_calls_per_episode} "
        "user and assistant calls without such retries.",
    ]
    unknown = [role.role for role in estimate.roles if role.cost_usd is None]
    if unknown:
        from pare.agents.models.backends import litellm_available
        from pare.install import install_command

        if litellm_available():
            where = "litellm's price table does not know the model"
        else:
            where = "litellm, whose price table PARE reads, is not installed "
            where += f"({install_command('litellm')})"
        notes.append(
            f"No price for {', '.join(unknown)}: none in the configuration and {where}. "
            "Set models.<role>.prices in USD per million tokens "
            f"(e.g. --set 'models.{unknown[0]}.prices={{input: 0.1, output: 0.4}}')."
        )
    if plan.cache == "replay":
        notes.append("--cache replay: every call is read from the cache, so no provider is called.")
    for note in notes:
        console.print(plain_text(note), highlight=False)


def _span(span: Span, show: Callable[[float, float], str]) -> str:
    """``typical - upper``, both written in the unit that suits the larger."""
    scale = max(span.typical, span.upper)
    return f"{show(span.typical, scale)} - {show(span.upper, scale)}"


def _count(value: float, scale: float) -> str:
    if scale >= 1e6:
        return f"{value / 1e6:.1f}M"
    if scale >= 1e4:
        return f"{value / 1e3:.0f}k"
    return f"{value:,.0f}"


def _dollars(value: float, scale: float) -> str:
    return f"${value:,.2f}" if scale >= 1 else f"${value:.4f}"
