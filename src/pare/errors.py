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
import re
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
    close = closest_names(name, choices, limit=limit)
    if not close:
        return ""
    return " Did you mean " + " or ".join(f"'{c}'" for c in close) + "?"


_CHARACTER_CUTOFF = 0.6
"""How alike two names must be letter by letter (difflib's ratio) to be suggested."""

_SAME_WORD = 0.8
"""Words this alike letter by letter are one word misspelt or inflected (user, users; event, evnt)."""

_SYNONYMS = (
    frozenset({"add", "create", "new", "make"}),
    frozenset({"delete", "remove"}),
    frozenset({"edit", "update", "change", "modify"}),
    frozenset({"get", "read", "fetch"}),
    frozenset({"search", "find"}),
)
"""Verbs that tool names use for the same thing: ``create_calendar_event`` means ``add_calendar_event``."""

_WORDS = re.compile(r"[A-Z]+(?![a-z])|[A-Z]?[a-z]+|\d+")


def closest_names(name: str, choices: Iterable[str], *, limit: int = 3) -> list[str]:
    """The ``choices`` most likely meant by ``name``, best first (at most ``limit``).

    Two comparisons: letter by letter (a typo: ``recieve_email``), and word by word, for names written
    with the right words but one too many, too few or another (``send_message_to_users`` for
    ``send_message_to_user``, ``create_event`` for ``create_calendar_event``), which letters alone rank
    below names that merely share a long stretch. Names the same up to inflections and the verbs tools use
    alike (add / create) come first and alone, then names one word off (more words in common first), then
    names alike letter by letter. A word match needs two words in common, so ``set_day`` does not suggest
    every other ``set_*``.
    """
    candidates = list(dict.fromkeys(choices))
    words = _words(name)
    ranked: list[tuple[int, int, float, str]] = []
    for choice in candidates:
        ratio = difflib.SequenceMatcher(None, name, choice).ratio()
        distance, common = _word_distance(words, _words(choice))
        if distance == 0 and common >= 1:
            rank = 0
        elif distance == 1 and common >= 2:
            rank = 1
        elif ratio >= _CHARACTER_CUTOFF:
            rank = 2
        else:
            continue
        ranked.append((rank, -common if rank < 2 else 0, -ratio, choice))
    ranked.sort()
    if ranked and ranked[0][0] == 0:  # the same words: what was meant, not a guess among neighbours
        ranked = [entry for entry in ranked if entry[0] == 0]
    return [entry[-1] for entry in ranked[:limit]]


def _words(name: str) -> list[str]:
    return [word.lower() for word in _WORDS.findall(name)]


def _same_word(left: str, right: str) -> bool:
    if left == right:
        return True
    if any(left in group and right in group for group in _SYNONYMS):
        return True
    return difflib.SequenceMatcher(None, left, right).ratio() >= _SAME_WORD


def _word_distance(left: list[str], right: list[str]) -> tuple[int, int]:
    """The fewest words to add, drop or replace to turn ``left`` into ``right``, and how many words the
    two have in common along that way (words alike by :func:`_same_word` count as the same).
    """
    # Levenshtein over words; each cell keeps (edits, words in common), fewest edits first
    previous = [(column, 0) for column in range(len(right) + 1)]
    for row, word in enumerate(left, start=1):
        current = [(row, 0)]
        for column, other in enumerate(right, start=1):
            options = [
                (previous[column][0] + 1, previous[column][1]),
                (current[column - 1][0] + 1, current[column - 1][1]),
            ]
            if _same_word(word, other):
                options.append((previous[column - 1][0], previous[column - 1][1] + 1))
            else:
                options.append((previous[column - 1][0] + 1, previous[column - 1][1]))
            current.append(min(options, key=lambda cell: (cell[0], -cell[1])))
        previous = current
    return previous[-1]


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
