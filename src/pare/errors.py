"""The three families of errors in PARE, in one place.

* :class:`UserInputError` — the person running PARE made a mistake (bad option, broken scenario file).
  The command line prints these cleanly with what to do; they never become tracebacks.
* :class:`ToolError` — a tool call inside the simulation failed (no such email, argument of the wrong
  type, action not on this screen). These never escape the environment: they are returned to the actor
  as an error observation and recorded in the action log.
* :class:`SimulationBug` — an invariant of PARE itself was broken (an app declared one target screen and
  went to another). This is a bug in PARE or in an app definition, not in a model's behaviour.
"""

from __future__ import annotations

import difflib
from collections.abc import Iterable


class PareError(Exception):
    """Base class of every error PARE raises on purpose."""


class UserInputError(PareError):
    """A mistake in what the person running PARE gave it; the message says what and where."""


class ToolError(PareError):
    """A tool call failed; the message is shown to the calling actor as its observation."""


class SimulationBug(PareError):
    """An invariant of the simulation or of an app declaration does not hold."""


def did_you_mean(name: str, choices: Iterable[str], *, limit: int = 3) -> str:
    """Return ``" Did you mean 'x'?"`` for the closest choices, or an empty string."""
    close = difflib.get_close_matches(name, list(choices), n=limit, cutoff=0.6)
    if not close:
        return ""
    return " Did you mean " + " or ".join(f"'{c}'" for c in close) + "?"
