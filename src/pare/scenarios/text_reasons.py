"""Why a text fails a text operator, and how the operator is named in the explanation.

Each text operator's record (:mod:`pare.scenarios.operators`) points at its functions here; they run only
to explain a check that failed (:mod:`pare.scenarios.explain`), reading the text again clause by clause.
"""

from __future__ import annotations

import re
from datetime import date, datetime, time
from typing import Any

from pare.scenarios import meaning
from pare.scenarios.excerpts import excerpt
from pare.scenarios.matchers import reading_moment
from pare.scenarios.times import TimeFormatError, parse_time


# -- how an operator is named, with what it wants -----------------------------------------------------------
def pieces_label(name: str, pieces: tuple[str, ...], start: datetime) -> str:
    """``contains 'thursday', '3'``."""
    return f"{name} " + ", ".join(repr(piece) for piece in pieces)


def regex_label(pattern: re.Pattern[str], start: datetime) -> str:
    """``regex '^Dear'``."""
    return f"regex {pattern.pattern!r}"


def declines_label(wanted: bool, start: datetime) -> str:
    """``declines true``."""
    return f"declines {str(wanted).lower()}"


def clock_label(clock: time, start: datetime) -> str:
    """``mentions_clock 18:15``."""
    return f"mentions_clock {clock.strftime('%H:%M')}"


def moment_label(name: str, expected: Any, start: datetime) -> str:
    """A day or a time with a relative one resolved: ``mentions_day day+3 (Thu 6 Mar)``."""
    moment = _resolved(expected, start)
    written = expected if isinstance(expected, str) else expected.isoformat()
    if name == "mentions_day":
        written = written.removesuffix(" 00:00")  # how a day alone was compiled (see the operators)
    if moment is None:
        return f"{name} {written}"
    resolved = _shown_day(moment.date()) + ("" if name == "mentions_day" else " " + moment.strftime("%H:%M"))
    return f"{name} {written} ({resolved})"


# -- why a text fails ---------------------------------------------------------------------------------------
def why_not_affirmed(text: str, pieces: tuple[str, ...], start: datetime) -> str:
    """``affirms``: for each piece, the negated clauses that mention it, or that it is not there."""
    reasons = []
    for piece in pieces:
        if meaning.affirms(text, piece):
            continue
        negated = []
        for clause in meaning.clauses(text):
            word = meaning.found_word(clause, piece)
            if word is not None:
                cue = meaning.negation_cue(clause) or "?"
                shown = excerpt(clause, (cue, word))
                negated.append(f"found '{word}' in clause \"{shown}\" but it is negated by '{cue}'")
        if negated:
            reasons.append(f"{piece!r}: " + "; ".join(negated))
        else:
            reasons.append(f"{piece!r} is not in the text as a whole word{_inside(text, piece)}")
    return "; ".join(reasons) if len(pieces) > 1 else reasons[0].removeprefix(f"{pieces[0]!r}: ")


def why_not_contained(text: str, pieces: tuple[str, ...], start: datetime) -> str:
    """``contains``: the pieces that are not in the text as whole words."""
    missing = [piece for piece in pieces if not meaning.has_word(text, piece)]
    return "; ".join(
        f"{piece!r} is not in the text as a whole word{_inside(text, piece)}" for piece in missing
    )


def why_none_contained(text: str, pieces: tuple[str, ...], start: datetime) -> str:
    """``contains_any``: none is there as a whole word (and where one is inside a longer word)."""
    inside = "".join(_inside(text, piece) for piece in pieces)
    return "none of them is in the text as a whole word" + inside


def _inside(text: str, piece: str) -> str:
    """Where ``piece`` is in ``text`` only as part of a longer word (``wed`` in "reviewed"), if it is."""
    core = piece.strip("* ")
    found = re.search(r"\w*" + re.escape(core) + r"\w*", meaning.normalise_quotes(text), re.IGNORECASE)
    return f" (only inside '{found.group(0)}')" if found else ""


def why_not_found(text: str, pattern: re.Pattern[str], start: datetime) -> str:
    """``regex``: the pattern is not found."""
    return "not found in the text"


def why_declines_differs(text: str, wanted: bool, start: datetime) -> str:
    """``declines``: the clause that refuses (or takes up another option), or that none refuses."""
    found = meaning.refusal(text)
    if not wanted:
        hedged = meaning.hedge(text)
        if found is None and hedged is not None:
            return f"it hedges ('{hedged}'), with no firm answer beside it: no answer yet"
        assert found is not None  # declines() held
        return f"it reads as a refusal: clause \"{excerpt(found.clause, (found.cue,))}\" has '{found.cue}'"
    if found is None:
        return 'no clause refuses (no phrase such as "can\'t make", "doesn\'t work", "no thanks")'
    assert found.taken_up is not None
    clause, offer = found.taken_up
    return (
        f"clause \"{excerpt(found.clause, (found.cue,))}\" refuses ('{found.cue}') but a later clause "
        f"\"{excerpt(clause, (offer,))}\" takes up another option ('{offer}'): a counter-offer"
    )


def why_not_mentioned(text: str, expected: Any, start: datetime) -> str:
    """What days and times the text names, affirmed or negated, clause by clause."""
    named, negated = [], []
    for number, sentence in enumerate(meaning.sentence_clauses(text), start=1):
        for clause in sentence:
            found = meaning.mentions(clause, reading_moment(start))
            if not found:
                continue
            readings = ", ".join(_reading(mention) for mention in found)
            cue = meaning.negation_cue(clause)
            if cue is None:
                named.append(f"{readings} (sentence {number})")
            else:
                negated.append(f"{readings} in \"{excerpt(clause, (cue,))}\" negated by '{cue}'")
    if named:
        said = f"the text names {', '.join(named)}"
    else:
        said = "the text names days or times only in negated clauses" if negated else "the text names none"
    return said + ("; " + "; ".join(negated) if negated else "")


def _reading(mention: meaning.Mention) -> str:
    days = "/".join(_shown_day(day) for day in sorted(mention.days))
    times = "/".join(clock.strftime("%H:%M") for clock in sorted(mention.times))
    return " ".join(part for part in (days, times) if part)


def _shown_day(day: date) -> str:
    return f"{day:%a} {day.day} {day:%b}"


def _resolved(expected: Any, start: datetime) -> datetime | None:
    if isinstance(expected, time):
        return None
    try:
        return parse_time(expected, start)
    except (TimeFormatError, TypeError):
        return None
