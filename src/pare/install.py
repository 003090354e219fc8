"""How to install PARE and its extras: the distribution's name and the command a message should suggest.

The import name is ``pare``, but the distribution is ``pare-bench``: the name ``pare`` on the package
registry belongs to an unrelated project, so installing ``pare`` by name (with any extra) would install that
project.
"""

from __future__ import annotations

import functools
from pathlib import Path

DISTRIBUTION = "pare-bench"
"""The name PARE is installed under (``pip show pare-bench``, ``importlib.metadata.version``)."""


@functools.cache
def _source_checkout() -> Path | None:
    """The checkout this package was installed from in editable mode, if it is one."""
    root = Path(__file__).resolve().parents[2]
    project = root / "pyproject.toml"
    try:
        text = project.read_text(encoding="utf-8")
    except OSError:
        return None
    return root if f'name = "{DISTRIBUTION}"' in text else None


def install_command(extra: str) -> str:
    """The command that adds ``extra`` to this installation of PARE.

    From a source checkout (the usual case: an editable install), the checkout's own path, so the command
    works whatever the current folder; otherwise the distribution's name.
    """
    checkout = _source_checkout()
    if checkout is not None:
        return f'pip install -e "{checkout}[{extra}]"'
    return f'pip install "{DISTRIBUTION}[{extra}]"'
