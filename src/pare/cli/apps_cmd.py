"""``pare apps``: list the apps, their screens, actions and tools; export their FSM as Mermaid."""

from __future__ import annotations

from typing import Annotated

import typer

from pare.errors import UserInputError

# The apps and rich are imported by the commands that use them: `pare --help` stays fast.

app = typer.Typer(
    help="The phone's apps: screens, user actions, agent tools.",
    invoke_without_command=True,
    rich_markup_mode=None,  # plain help: see pare.cli.app
)


@app.callback()
def list_apps(ctx: typer.Context) -> None:
    """List every app with its screens and how many agent tools of each kind it has."""
    if ctx.invoked_subcommand is not None:
        return
    from rich.console import Console
    from rich.table import Table

    from pare.apps.registry import get_app_class, phone_apps
    from pare.apps.system import SystemApp

    table = Table(title="PARE apps")
    for column in ("app", "screens (root first)", "read", "write", "env"):
        table.add_column(column)
    for name in phone_apps():
        cls = get_app_class(name)
        kinds = [spec.kind for spec in cls.tools.values()]
        table.add_row(
            name,
            ", ".join(s.screen_name() for s in cls.screens)
            or "(none: the assistant's API; users attach by path)",
            str(kinds.count("read")),
            str(kinds.count("write")),
            str(kinds.count("env")),
        )
    shell = ", ".join(SystemApp.tools)
    Console().print(table)
    Console().print(
        f"[bold]shell[/bold] (system): {shell}; plus accept_proposal / reject_proposal while a "
        "proposal is pending."
    )


@app.command("show")
def show_app(
    name: Annotated[str, typer.Argument(help="The app, e.g. email.")],
    mermaid: Annotated[
        bool, typer.Option("--mermaid", help="Print the screen FSM as a Mermaid diagram.")
    ] = False,
    seed: Annotated[
        bool, typer.Option("--seed", help="Print the format of the app's seed data in scenario files.")
    ] = False,
) -> None:
    """Show an app's screens with their user actions, and its agent tools."""
    from rich.console import Console
    from rich.table import Table

    from pare.apps.fsm import to_mermaid
    from pare.apps.registry import get_app_class
    from pare.apps.screens import BACK, STAY
    from pare.scenarios.seed_format import seed_format

    cls = get_app_class(name)
    if seed:
        typer.echo("\n".join(seed_format(cls.name)))
        return
    if mermaid:
        if not cls.screens:
            raise UserInputError(f"'{name}' has no screens, so there is no diagram to draw.")
        typer.echo(to_mermaid(cls), nl=False)
        return
    console = Console()
    console.print(f"[bold]{cls.title}[/bold] ({cls.name}) — {cls.description}")
    for screen in cls.screens:
        table = Table(title=f"screen {screen.screen_name()}", title_justify="left")
        for column in ("user action", "kind", "leads to"):
            table.add_column(column)
        for spec in screen.actions.values():
            targets = ", ".join({STAY: "(stay)", BACK: "(back)"}.get(t, t) for t in spec.leads_to)
            table.add_row(spec.signature, spec.kind, targets)
        console.print(table)
    table = Table(title="agent tools", title_justify="left")
    for column in ("tool", "kind", "description"):
        table.add_column(column)
    for spec in cls.tools.values():
        kind = spec.kind if spec.harm is None else f"{spec.kind}, {spec.harm}"  # how bad a wrong call is
        table.add_row(spec.qualified_name + spec.signature[len(spec.name) :], kind, spec.summary)
    console.print(table)
