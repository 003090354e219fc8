"""``pare view``: read runs in the browser (served on 127.0.0.1, or written as a static site)."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from pare.errors import UserInputError
from pare.install import install_command


def view(
    runs: Annotated[
        list[Path],
        typer.Argument(help="Run folders, or sweep folders (every run inside is shown).", show_default=False),
    ],
    port: Annotated[
        int, typer.Option("--port", help="Port to serve on (0: a free one).", min=0, max=65535)
    ] = 0,
    host: Annotated[
        str, typer.Option("--host", help="Loopback address to serve on (127.0.0.1, ::1 or localhost).")
    ] = "127.0.0.1",
    export: Annotated[
        Path | None,
        typer.Option("--export", help="Write the pages as a static site into this folder instead."),
    ] = None,
) -> None:
    """Open runs in the browser: the configurations with their metrics, the episodes table with filters,
    each episode turn by turn with the phone as the user saw it, and two configurations side by side.
    Read-only; served on the loopback interface only. Needs the ``viewer`` extra.
    """
    try:
        from pare.viewer import Catalog, Site, export_site
        from pare.viewer._server import bind, serve, url_of
    except ImportError as error:
        raise UserInputError(
            f"pare view needs the viewer extra ({error.name} is missing): {install_command('viewer')}"
        ) from None
    site = Site(Catalog.open(runs))
    if export is not None:
        if not export.exists():  # a path through a file, or where the system refuses a folder: said here
            from pare.output_paths import make_output_folder

            make_output_folder(export, "the --export folder")
        written = export_site(site, export)
        typer.echo(f"wrote {written} files; open {export / 'index.html'}")
        return
    sock = bind(host, port)
    typer.echo(f"PARE viewer on {url_of(sock)}  (read-only but for annotations; Ctrl+C to stop)", err=False)
    try:
        serve(site, sock)
    finally:
        sock.close()
