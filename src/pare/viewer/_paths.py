"""Confinement: every file the viewer reads lies inside the run folders it was given.

URLs never name files: a page is looked up by configuration id, scenario and run, and the file comes
from the run's own episode record. That record is data like any other, so its path is checked too: a
relative path without ``..``, backslashes or drive letters, which after resolving symbolic links still
lies inside the run folder.
"""

from __future__ import annotations

import hashlib
import re
from pathlib import Path, PurePosixPath

_SAFE_NAME = re.compile(r"[A-Za-z0-9][A-Za-z0-9_.-]{0,99}")


class OutsideRunError(LookupError):
    """A path that would leave the run folders (or is not a plain relative path)."""


def confined(root: Path, relative: str) -> Path:
    """``root / relative``, refused unless it is a plain relative path that stays inside ``root``
    once every symbolic link is resolved.
    """
    if not relative or "\\" in relative or "\x00" in relative or ":" in relative:
        raise OutsideRunError(f"not a plain relative path: {relative!r}")
    parts = PurePosixPath(relative).parts
    if PurePosixPath(relative).is_absolute() or any(part in ("..", ".") for part in parts):
        raise OutsideRunError(f"not a plain relative path: {relative!r}")
    base = root.resolve()
    target = (base / relative).resolve()
    if not target.is_relative_to(base):
        raise OutsideRunError(f"{relative!r} leads outside {root}")
    return target


def slug(name: str) -> str:
    """A name safe as one URL segment and one file name: ``name`` itself when it already is one, else a
    readable prefix and a hash (so two different names never share a slug).
    """
    if _SAFE_NAME.fullmatch(name) and name not in (".", ".."):
        return name
    readable = re.sub(r"[^A-Za-z0-9_-]+", "-", name).strip("-")[:40] or "x"
    return f"{readable}~{hashlib.sha256(name.encode('utf-8')).hexdigest()[:10]}"
