"""The families of errors in PARE, in one place.

* :class:`UserInputError` — the person running PARE made a mistake (bad option, broken scenario file).
  The command line prints these cleanly with what to do; they never become tracebacks.
* :class:`ToolError` — a tool call inside the simulation failed (no such email, argument of the wrong
  type, action not on this screen). These never escape the environment: they are returned to the actor
  as an error observation and recorded in the action log.
* :class:`RunFailure` — the infrastructure failed (a model provider stayed unavailable through every
  retry). Recorded with a reason and reported as missing coverage, never as a failure of the model.
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


class ActionFormatError(ToolError):
    """A model's answer is not one tool call in the Thought/Action format; the message, written for the
    model, says what was wrong and how to answer, and is returned to it as its observation.
    """

    def __init__(self, message: str, *, kind: str = "format") -> None:
        super().__init__(message)
        self.kind = kind
        """A short stable code for the failure (``"no_action"``, ``"invalid_json"``, ...), for counting."""


class SimulationBug(PareError):
    """An invariant of the simulation or of an app declaration does not hold."""


def first_error(errors: BaseExceptionGroup[BaseException]) -> BaseException:
    """The error to report from a task group: the first :class:`UserInputError` (a mistake the person can
    fix), else the first error.
    """
    leaves: list[BaseException] = []
    stack: list[BaseException] = [errors]
    while stack:
        error = stack.pop(0)
        if isinstance(error, BaseExceptionGroup):
            stack.extend(error.exceptions)
        else:
            leaves.append(error)
    return next((error for error in leaves if isinstance(error, UserInputError)), leaves[0])


def did_you_mean(name: str, choices: Iterable[str], *, limit: int = 3) -> str:
    """Return ``" Did you mean 'x'?"`` for the closest choices, or an empty string."""
    close = difflib.get_close_matches(name, list(choices), n=limit, cutoff=0.6)
    if not close:
        return ""
    return " Did you mean " + " or ".join(f"'{c}'" for c in close) + "?"


class ModelRequestError(UserInputError):
    """A model provider refused a request for a reason retrying cannot fix.

    A bad or missing API key, an unknown model, a wrong endpoint, a prompt longer than the model's
    context, a request the provider rejects. The message names the role, the model and the endpoint and
    says what to change. ``kind`` is a short machine-readable reason (``"missing_api_key"``,
    ``"authentication"``, ``"permission"``, ``"not_found"``, ``"context_length"``, ``"quota"``,
    ``"bad_request"``) and ``status_code`` the HTTP status when there was one.
    """

    def __init__(self, message: str, *, kind: str = "bad_request", status_code: int | None = None) -> None:
        super().__init__(message)
        self.kind = kind
        self.status_code = status_code


class CacheMiss(UserInputError):
    """A model call was not in the record/replay cache while the cache allows replay only."""


class RunFailure(PareError):
    """A run could not finish for reasons outside PARE and outside the models' behaviour.

    This is the family of infrastructure failures (a provider down, rate-limited past every retry). The
    benchmark runner records them with their reason and reports the episode as missing coverage; they
    never count as a model's failure.
    """


class ProviderUnavailable(RunFailure):
    """A model provider kept failing with transient errors (rate limits, 5xx, timeouts) past every retry.

    ``attempts`` is the number of requests made and ``status_code`` the HTTP status of the last failure
    when there was one.
    """

    def __init__(self, message: str, *, attempts: int = 0, status_code: int | None = None) -> None:
        super().__init__(message)
        self.attempts = attempts
        self.status_code = status_code
