"""Writing the site as static files: the same pages, opened from disk or published with a paper."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

from pare.errors import UserInputError
from pare.viewer._site import Site


def export_site(site: Site, folder: Path, progress: Callable[[int], None] | None = None) -> int:
    """Write every page of ``site`` under ``folder`` and return how many files were written.

    Raises:
        UserInputError: ``folder`` exists and is neither empty nor an earlier export, or the system
            refused a write (a full disk).
    """
    if folder.exists():
        if not folder.is_dir():
            raise UserInputError(f"{folder} is a file; --export needs a folder")
        if any(folder.iterdir()) and not (folder / "index.html").exists():
            raise UserInputError(f"{folder} is not empty and holds no earlier export; choose another folder")
    base = folder.resolve()
    written = 0
    for path in site.paths():
        page = site.page(path)
        if page is None:  # an episode listed but not renderable cannot happen; skip rather than guess
            continue
        target = (base / path).resolve()
        if not target.is_relative_to(base):  # paths come from slugs, so this only guards against a bug
            raise UserInputError(f"refusing to write {path!r} outside {folder}")
        try:
            target.parent.mkdir(parents=True, exist_ok=True)
            target.write_bytes(page.body)
        except OSError as error:  # a full disk, a read-only folder: say so in one line
            raise UserInputError(
                f"{target}: cannot write the site: {error.strerror or error} "
                f"({written} of its files written; fix this and export again)"
            ) from None
        written += 1
        if progress is not None:
            progress(written)
    return written
