"""``pare doctor``: one small call per configured role, before spending a run on a broken setting."""

from __future__ import annotations

import json
from typing import TYPE_CHECKING, Annotated, Any

import typer

from pare.cli.run_cmd import (
    AssistantEndpoint,
    AssistantModel,
    AssistantProvider,
    ConfigFile,
    ExecuteEndpoint,
    ExecuteModel,
    ExecuteProvider,
    JudgeEndpoint,
    JudgeModel,
    JudgeProvider,
    ObserveEndpoint,
    ObserveModel,
    ObserveProvider,
    Sets,
    UserEndpoint,
    UserModel,
    UserProvider,
    collect_overrides,
    load_config,
    role_models,
)
from pare.errors import UserInputError

if TYPE_CHECKING:
    from rich.console import Console

    from pare.agents.models.config import ModelConfig
    from pare.agents.models.doctor import RoleCheck


def doctor(
    config_file: ConfigFile = None,
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
    generator_model: Annotated[
        str | None,
        typer.Option(
            "--generator-model",
            help="Also check pare generate's model.",
            envvar="PARE_GENERATOR_MODEL",
            show_default=False,
        ),
    ] = None,
    generator_provider: Annotated[
        str, typer.Option("--generator-provider", help="openai or litellm.")
    ] = "openai",
    generator_endpoint: Annotated[
        str | None, typer.Option("--generator-endpoint", help="Base URL of the generator's server.")
    ] = None,
    sets: Sets = None,
    output_format: Annotated[str, typer.Option("--format", help="text (default) or json.")] = "text",
) -> None:
    """Check each configured model with one small call: what was sent and accepted, latency, tokens, price.

    Takes the same configuration as `pare run` (a file, the role flags, --set), plus the generator's
    model. Exits 0 when every role answered, 1 when one did not (with what to change).
    """
    import asyncio
    import logging

    from pare.agents.models.doctor import check_roles
    from pare.terminal_text import make_console

    if output_format not in ("text", "json"):
        raise UserInputError(f"--format is text or json, not '{output_format}'")
    models = role_models(
        user=(user_model, user_provider, user_endpoint),
        assistant=(assistant_model, assistant_provider, assistant_endpoint),
        observe=(observe_model, observe_provider, observe_endpoint),
        execute=(execute_model, execute_provider, execute_endpoint),
        judge=(judge_model, judge_provider, judge_endpoint),
    )
    config = load_config(config_file, collect_overrides(sets=sets, flags={}, models=models))
    roles: dict[str, ModelConfig] = dict(config.models.roles())
    if generator_model is not None:
        roles["generator"] = generator_config(generator_model, generator_provider, generator_endpoint)
    console = make_console()
    if not roles:
        console.print(
            "No role has a model, so there is nothing to check: an oracle run calls no provider. Name the "
            "models as for pare run (--user-model, --assistant-model, ..., or -c run.yaml)."
        )
        return
    # Each adjustment and retry is part of the report below; the client's warnings would say it twice.
    models_log = logging.getLogger("pare.models")
    level = models_log.level
    models_log.setLevel(logging.ERROR)
    try:
        checks = asyncio.run(check_roles(roles))
    finally:
        models_log.setLevel(level)
    if output_format == "json":
        typer.echo(json.dumps([check.to_json() for check in checks], indent=2))
    else:
        print_checks(checks, console)
    if not all(check.ok for check in checks):
        raise typer.Exit(1)


def generator_config(model: str, provider: str, endpoint: str | None) -> ModelConfig:
    """The generator's model configuration as ``pare generate`` makes it from the same three flags."""
    from pare.agents.models.config import ModelConfig
    from pare.cli.generate_cmd import generator_settings

    data = generator_settings(model=model, provider=provider, endpoint=endpoint)
    return ModelConfig.parse(data, where="--generator-model")


def print_checks(checks: list[RoleCheck], console: Console) -> None:
    """One block per configuration checked: the outcome line, then what was sent, then advice (the
    model's answer and the provider's words shown as text: see :mod:`pare.terminal_text`).
    """
    from pare.terminal_text import markup_safe, plain_text

    for check in checks:
        roles = " + ".join(check.roles)
        where = f"{markup_safe(check.model)} at {markup_safe(check.endpoint)}"
        head = f"[green]ok[/green]    {roles}: {where}" if check.ok else f"[red]FAIL[/red]  {roles}: {where}"
        console.print(head, highlight=False)
        lines: list[str] = [f"key: {_key(check)}", f"sent: {_params(check.sent)}"]
        for adjustment in check.adjustments:
            learned = "learned from the provider's refusal" if adjustment.get("learned") else "known"
            change = f"sent as {adjustment['to']}" if adjustment["action"] == "renamed" else "not sent"
            lines.append(f"adjusted: {adjustment['param']} {change} ({learned}: {adjustment['why']})")
        if check.ok:
            lines.append(
                f"answered by {check.answered_by} in {check.latency_s or 0.0:.2f} s: {check.answer!r}"
                + (" (with reasoning)" if check.reasoning else "")
            )
            lines.append(f"tokens: {_tokens(check)}; price: {_price(check)}")
        else:
            lines.append(f"problem: {check.problem}")
        for line in lines:
            console.print(plain_text(f"      {line}"), highlight=False, soft_wrap=False)
    failed = sum(not check.ok for check in checks)
    if failed:
        console.print(f"[red]{failed} of {len(checks)} model setting(s) failed[/red]: fix them before a run.")
    else:
        console.print(f"[green]every model answered[/green] ({len(checks)} checked).")


def _key(check: RoleCheck) -> str:
    if check.key_variable is None:
        if check.backend == "litellm":
            return "the provider's usual variable, found by litellm"
        return "none sent (a local server)"
    return f"{check.key_variable} ({'set' if check.key_found else 'NOT SET'})"


def _params(params: dict[str, Any]) -> str:
    if not params:
        return "no sampling parameter (the provider's defaults)"
    return ", ".join(f"{name}={json.dumps(value)}" for name, value in params.items())


def _tokens(check: RoleCheck) -> str:
    cached = f" ({check.cached_tokens} cached)" if check.cached_tokens else ""
    return f"{check.prompt_tokens} in{cached}, {check.completion_tokens} out"


def _price(check: RoleCheck) -> str:
    if check.price_source is None:
        return "unknown (set prices in the configuration to count cost)"
    cost = "unknown" if check.cost_usd is None else f"${check.cost_usd:.6f}"
    return f"{cost} for this call (prices from {check.price_source})"
