"""``pare play SCENARIO``: a person plays the user, at the terminal or in the browser, against any
configured assistant (the oracle by default); the episode is recorded as a run.
"""

from __future__ import annotations

import asyncio
from collections.abc import Coroutine
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any, TypeVar

import typer

from pare.cli.run_cmd import (
    AssistantEndpoint,
    AssistantModel,
    AssistantPolicyName,
    AssistantProvider,
    ConfigFile,
    ExecuteEndpoint,
    ExecuteModel,
    ExecuteProvider,
    JudgeEndpoint,
    JudgeProvider,
    ObserveEndpoint,
    ObserveModel,
    ObserveProvider,
    ProtocolFlag,
    Sets,
    collect_overrides,
    load_config,
    role_models,
)
from pare.errors import UserInputError
from pare.install import install_command

T = TypeVar("T")

if TYPE_CHECKING:
    from rich.console import Console

    from pare.bench.play import Seat
    from pare.bench.runner import EpisodeOutput


JudgeModel = Annotated[
    str | None,
    typer.Option(
        "--judge-model",
        help="Judge of free-text checks (default: their deterministic fallbacks).",
        show_default=False,
    ),
]


def play(
    scenario: Annotated[
        str, typer.Argument(help="A scenario id, or the path of a scenario file.", show_default=False)
    ],
    browser: Annotated[
        bool, typer.Option("--browser", help="Play on the phone in the browser instead of the terminal.")
    ] = False,
    port: Annotated[
        int,
        typer.Option("--port", help="With --browser: port to serve on (0: a free one).", min=0, max=65535),
    ] = 0,
    host: Annotated[
        str, typer.Option("--host", help="With --browser: loopback address (127.0.0.1, ::1 or localhost).")
    ] = "127.0.0.1",
    config_file: ConfigFile = None,
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
    assistant_policy: AssistantPolicyName = None,
    protocol: ProtocolFlag = None,
    max_turns: Annotated[
        int | None, typer.Option("--max-turns", help="Turns in the episode (default 10).")
    ] = None,
    seed: Annotated[int | None, typer.Option("--seed", help="Base seed (default 0).")] = None,
    tool_failure_prob: Annotated[
        float | None,
        typer.Option("--tool-failure-prob", help="Chance an assistant tool call fails (default 0)."),
    ] = None,
    noise_rate: Annotated[
        float | None,
        typer.Option("--noise-rate", help="Distractor notifications per simulated minute (default 0)."),
    ] = None,
    name: Annotated[str | None, typer.Option("--name", help="A label for reports and the folder.")] = None,
    output: Annotated[
        str | None, typer.Option("--output", "-o", help="Run folder (default runs/<label>-<identity>).")
    ] = None,
    sets: Sets = None,
) -> None:
    """Be the user in one scenario: each turn you see the phone as the user model would and take one
    action, against the configured assistant (the scenario's oracle by default). The episode is recorded
    in a run folder when it ends (the next run of the scenario there), for pare report and pare view;
    quitting or Ctrl+C before the end records nothing.
    """
    from pare.bench.build import check_credentials
    from pare.bench.play import PLAY_SETTINGS, prepare
    from pare.terminal_text import make_console

    path = Path(scenario)
    selection: dict[str, list[str]] = (
        {"paths": [scenario]} if path.suffix in (".yaml", ".yml") else {"ids": [scenario]}
    )
    flags = {
        "name": name,
        "seed": seed,
        "output": output,
        "policies.assistant": assistant_policy,
        "protocol.preset": protocol,
        "protocol.max_turns": max_turns,
        "world.tool_failure_probability": tool_failure_prob,
        "world.noise_rate_per_minute": noise_rate,
    }
    models = role_models(
        assistant=(assistant_model, assistant_provider, assistant_endpoint),
        observe=(observe_model, observe_provider, observe_endpoint),
        execute=(execute_model, execute_provider, execute_endpoint),
        judge=(judge_model, judge_provider, judge_endpoint),
    )
    overrides: list[tuple[str, Any]] = collect_overrides(sets=sets, flags=flags, models=models)
    overrides += [("scenarios", selection), *PLAY_SETTINGS]
    config = load_config(config_file, overrides)
    seat = prepare(config)
    check_credentials(config)
    console = make_console()
    _introduce(seat, console)
    played = _play_in_browser(seat, console, host, port) if browser else _play_at_terminal(seat, console)
    if played is None:
        raise typer.Exit(1)


def _introduce(seat: Seat, console: Console) -> None:
    from pare.terminal_text import markup_safe

    scenario = seat.plan.scenario
    roles = seat.config.policy_names()
    judge = seat.config.judge_provenance()
    console.print(
        f"[bold]{markup_safe(scenario.id)}[/bold] — {markup_safe(scenario.title)}\n"
        f"assistant: {markup_safe(seat.config.label())}; policies: "
        + ", ".join(f"{role} {markup_safe(name)}" for role, name in roles.items())
        + f"; judge: {markup_safe(judge['model'] or 'deterministic fallbacks')}\n"
        f"recorded when it ends as run {seat.plan.run} in {markup_safe(seat.folder)}",
        highlight=False,
    )


def _play_at_terminal(seat: Seat, console: Console) -> EpisodeOutput | None:
    from pare.agents.human_input import SeatLeft
    from pare.agents.terminal_user import TerminalUser
    from pare.bench.play import play
    from pare.errors import RunFailure

    scenario = seat.plan.scenario
    user = TerminalUser(console, persona=scenario.user.persona, goal=scenario.user.goal)
    try:
        output = _run_at_terminal(play(seat, user))
    except SeatLeft:
        console.print("[yellow]you left[/yellow]: the episode was not finished, so nothing was recorded.")
        return None
    except KeyboardInterrupt:
        console.print("[yellow]interrupted[/yellow]: the episode was not finished, so nothing was recorded.")
        raise typer.Exit(130) from None
    except RunFailure as error:
        raise UserInputError(
            f"the assistant's model could not be reached, nothing was recorded: {error}"
        ) from None
    for line in _settle(seat, output):
        console.print(line, markup=False, highlight=False, soft_wrap=True)
    return output


def _run_at_terminal(episode: Coroutine[Any, Any, T]) -> T:
    """Run ``episode`` in an event loop of its own, leaving Ctrl+C to Python's default handler.

    ``asyncio.run`` answers Ctrl+C by cancelling the episode at its next pause, but a person deciding is
    a blocking read with no pause: the interrupt would wait for the next Enter. Here it interrupts the
    read at once, and the episode's model clients close on the way out.
    """
    loop = asyncio.new_event_loop()
    try:
        return loop.run_until_complete(episode)
    finally:
        try:
            for task in asyncio.all_tasks(loop):
                task.cancel()
            loop.run_until_complete(loop.shutdown_asyncgens())
        finally:
            loop.close()


def _play_in_browser(seat: Seat, console: Console, host: str, port: int) -> EpisodeOutput | None:
    try:
        from pare.viewer._play import BrowserUser, Outcome, serve_episode
        from pare.viewer._server import bind, url_of
    except ImportError as error:
        raise UserInputError(
            f"pare play --browser needs the viewer extra ({error.name} is missing): "
            + install_command("viewer")
        ) from None
    from pare.agents.human_input import SeatLeft
    from pare.bench.play import play
    from pare.errors import RunFailure

    scenario = seat.plan.scenario
    user = BrowserUser(persona=scenario.user.persona, goal=scenario.user.goal)
    recorded: list[EpisodeOutput] = []

    def settle(output: EpisodeOutput) -> Outcome:
        lines = _settle(seat, output)
        recorded.append(output)
        for line in lines:
            console.print(line, markup=False, highlight=False, soft_wrap=True)
        console.print("close the page (or press Ctrl+C) to stop the server", highlight=False)
        return Outcome(lines, output.record.success if output.record.complete else None)

    sock = bind(host, port)
    console.print(f"play in the browser: {url_of(sock)}  (127.0.0.1 only; Ctrl+C to stop)", highlight=False)
    try:
        return asyncio.run(serve_episode(user, sock, lambda: play(seat, user), settle))
    except SeatLeft:
        console.print("[yellow]you left[/yellow]: the episode was not finished, so nothing was recorded.")
        return None
    except KeyboardInterrupt:
        if recorded:  # the episode is recorded: Ctrl+C only stopped the server
            return recorded[0]
        console.print("[yellow]interrupted[/yellow]: the episode was not finished, so nothing was recorded.")
        raise typer.Exit(130) from None
    except RunFailure as error:
        raise UserInputError(
            f"the assistant's model could not be reached, nothing was recorded: {error}"
        ) from None
    finally:
        sock.close()


def _settle(seat: Seat, output: EpisodeOutput) -> list[str]:
    """Record the episode and say how it went: the verdict, each goal, and where it is."""
    from pare.bench.play import record
    from pare.terminal_text import printable

    folder = record(seat, output)
    record_ = output.record
    if not record_.complete:
        failure = record_.failure
        reason = failure.message.splitlines()[-1] if failure is not None and failure.message else "unknown"
        lines = [f"the episode could not be played to its end ({reason}); recorded as failed"]
    else:
        verdict = "success: every goal met" if record_.success else "failed: not every goal was met"
        lines = [f"{verdict} in {record_.turns} turns ({record_.ended})"]
        descriptions = {goal.id: goal.description for goal in seat.plan.scenario.goals}
        for goal_id, passed in record_.goals.items():
            lines.append(f"  {'met' if passed else 'NOT met'}: {goal_id} — {descriptions.get(goal_id, '')}")
        for proposal in record_.proposals:
            lines.append(f"  proposal {proposal.proposal_id}: {proposal.resolution} — {proposal.content}")
    lines.append(f"recorded as run {seat.plan.run} in {folder}; see it with: pare view {folder}")
    return [printable(line) for line in lines]
