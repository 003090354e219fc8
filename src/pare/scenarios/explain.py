"""Why a matcher refused a value, in words an author can act on.

A failing check used to say only which matcher failed on how many texts ("fallback any of (affirms
['move*'] | ...) fails on 1 text(s)"); the author then had to read the matcher code to learn that the
clause holding "move" was negated by a "not" three words earlier. :func:`explain` says which part of the
matcher failed on which clause and why: ``affirms 'move*': found 'move' in clause "not Fri ... could we
move it" but it is negated by 'not'``.

Explanations are computed only for checks that fail (they read the text again, clause by clause), never
while checks run: a verdict's cost does not change when everything holds.
"""

from __future__ import annotations

import re
from collections.abc import Callable, Mapping, Sequence
from datetime import date, datetime, time
from typing import Any

from pare.scenarios import meaning
from pare.scenarios.matchers import Matcher, reading_moment
from pare.scenarios.operators import item_texts
from pare.scenarios.times import TimeFormatError, parse_time

TEXT_WIDTH = 80
"""The most characters of a text quoted in an explanation."""
CLAUSE_WIDTH = 60
"""The most characters of a clause quoted in an explanation."""
_MOST_ITEMS = 3
"""How many items of a list value are explained one by one."""


def explain(matcher: Matcher, value: Any, start: datetime) -> str:
    """Why ``matcher`` does not accept ``value`` (relative times resolved against ``start``); empty if it
    does. Each failing part is named with what it found, e.g. ``affirms 'move*': found 'move' in clause
    "not Fri ..." but it is negated by 'not'``.
    """
    if matcher.test(value, start):
        return ""
    if matcher.fields:
        return _explain_fields(matcher, value, start)
    reasons = []
    for name, expected in matcher.operators:
        single = Matcher(operators=((name, expected),))
        if not single.test(value, start):
            reasons.append(_explain_operator(single, name, expected, value, start))
    return "; ".join(reasons)


def quote(text: str, width: int = TEXT_WIDTH) -> str:
    """``text`` on one line in double quotes, shortened in the middle to about ``width`` characters."""
    return '"' + excerpt(text, (), width) + '"'


def excerpt(text: str, marks: Sequence[str] = (), width: int = CLAUSE_WIDTH) -> str:
    """``text`` on one line, at most about ``width`` characters: its start and its end, or when ``marks``
    are given, the words around each of them (``not Fri ... could we move it``), cut at spaces.
    """
    text = " ".join(text.split())
    if len(text) <= width:
        return text
    lowered = text.lower()
    spans = [(at, at + len(mark)) for mark in marks if mark and (at := lowered.find(mark.lower())) >= 0]
    if not spans:
        head = width * 3 // 5
        return _cut(text, 0, head) + " … " + _cut(text, len(text) - (width - head - 3), len(text))
    pad = max(6, (width - sum(end - begin for begin, end in spans)) // (2 * len(spans)))
    windows: list[tuple[int, int]] = []
    for begin, end in sorted(spans):
        window = (max(0, begin - pad), min(len(text), end + pad))
        if windows and window[0] <= windows[-1][1]:
            windows[-1] = (windows[-1][0], max(windows[-1][1], window[1]))
        else:
            windows.append(window)
    pieces = [_cut(text, begin, end) for begin, end in windows]
    shown = " … ".join(pieces)
    if windows[0][0] > 0:
        shown = "… " + shown
    if windows[-1][1] < len(text):
        shown += " …"
    return shown


def _cut(text: str, begin: int, end: int) -> str:
    """``text[begin:end]`` without the partial words at its edges (unless that leaves nothing)."""
    part = text[begin:end]
    if begin > 0 and text[begin - 1] != " " and " " in part:
        part = part[part.index(" ") + 1 :]
    if end < len(text) and text[end] != " " and " " in part:
        part = part[: part.rindex(" ")]
    return part.strip()


def _explain_fields(matcher: Matcher, value: Any, start: datetime) -> str:
    if isinstance(value, list):
        if not value:
            return "the list is empty"
        shown = [
            f"item {index}: {_explain_fields(matcher, item, start)}"
            for index, item in enumerate(value[:_MOST_ITEMS])
        ]
        more = f"; and {len(value) - _MOST_ITEMS} more" if len(value) > _MOST_ITEMS else ""
        return f"none of its {len(value)} items matches ({'; '.join(shown)}{more})"
    if not isinstance(value, Mapping):
        return f"not a record (got {_shown(value)})"
    reasons = []
    for key, field_matcher in matcher.fields:
        why = explain(field_matcher, value.get(key), start)
        if why:
            reasons.append(f"{key}: {why}")
    return "; ".join(reasons)


def _explain_operator(single: Matcher, name: str, expected: Any, value: Any, start: datetime) -> str:
    described = single.describe()
    if name == "not":
        return f"not ({expected.describe()}): it holds"
    if name == "any_of":
        return "any of: none holds (" + " | ".join(explain(option, value, start) for option in expected) + ")"
    if name == "present":
        return "the value is missing" if expected else f"the value is given ({_shown(value)})"
    if value is None:
        return f"{described}: the value is missing"
    if name in _TEXT_EXPLAINERS:
        texts = item_texts(value, name)
        reasons = [_TEXT_EXPLAINERS[name](text, expected, start) for text in texts[:_MOST_ITEMS]]
        if len(texts) == 1:
            return f"{_label(name, expected, start)}: {reasons[0]}"
        pairs = zip(texts, reasons, strict=False)
        shown = "; ".join(f"{quote(text, CLAUSE_WIDTH)}: {why}" for text, why in pairs)
        more = f"; and {len(texts) - _MOST_ITEMS} more" if len(texts) > _MOST_ITEMS else ""
        return f"{_label(name, expected, start)}: in none of its {len(texts)} items ({shown}{more})"
    return f"{described}: got {_shown(value)}"


def _label(name: str, expected: Any, start: datetime) -> str:
    """An operator and what it wants, with a relative day resolved (``mentions_day day+3 (Thu 6 Mar)``)."""
    if name in ("affirms", "contains", "contains_any"):
        return f"{name} " + ", ".join(repr(piece) for piece in expected)
    if name == "regex":
        return f"regex {expected.pattern!r}"
    if name == "declines":
        return f"declines {str(expected).lower()}"
    if name == "mentions_clock":
        return f"mentions_clock {expected.strftime('%H:%M')}"
    moment = _moment(expected, start)
    written = expected if isinstance(expected, str) else expected.isoformat()
    if name == "mentions_day":
        written = written.removesuffix(" 00:00")  # how a day alone was compiled (see the matchers)
    if moment is None:
        return f"{name} {written}"
    resolved = _day(moment.date()) + ("" if name == "mentions_day" else " " + moment.strftime("%H:%M"))
    return f"{name} {written} ({resolved})"


# -- text operators ------------------------------------------------------------------------------------
def _affirms(text: str, pieces: tuple[str, ...], start: datetime) -> str:
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


def _contains(text: str, pieces: tuple[str, ...], start: datetime) -> str:
    missing = [piece for piece in pieces if not meaning.has_word(text, piece)]
    return "; ".join(
        f"{piece!r} is not in the text as a whole word{_inside(text, piece)}" for piece in missing
    )


def _contains_any(text: str, pieces: tuple[str, ...], start: datetime) -> str:
    inside = "".join(_inside(text, piece) for piece in pieces)
    return "none of them is in the text as a whole word" + inside


def _inside(text: str, piece: str) -> str:
    """Where ``piece`` is in ``text`` only as part of a longer word (``wed`` in "reviewed"), if it is."""
    core = piece.strip("* ")
    found = re.search(r"\w*" + re.escape(core) + r"\w*", meaning.normalise_quotes(text), re.IGNORECASE)
    return f" (only inside '{found.group(0)}')" if found else ""


def _regex(text: str, pattern: re.Pattern[str], start: datetime) -> str:
    return "not found in the text"


def _declines(text: str, wanted: bool, start: datetime) -> str:
    found = meaning.refusal(text)
    if not wanted:
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


def _mentions(text: str, expected: Any, start: datetime) -> str:
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
    days = "/".join(_day(day) for day in sorted(mention.days))
    times = "/".join(clock.strftime("%H:%M") for clock in sorted(mention.times))
    return " ".join(part for part in (days, times) if part)


_TEXT_EXPLAINERS: dict[str, Callable[[str, Any, datetime], str]] = {
    "affirms": _affirms,
    "contains": _contains,
    "contains_any": _contains_any,
    "regex": _regex,
    "declines": _declines,
    "mentions_day": _mentions,
    "mentions_clock": _mentions,
    "mentions_time": _mentions,
}


# -- values ----------------------------------------------------------------------------------------------
def _day(day: date) -> str:
    return f"{day:%a} {day.day} {day:%b}"


def _moment(expected: Any, start: datetime) -> datetime | None:
    if isinstance(expected, time):
        return None
    try:
        return parse_time(expected, start)
    except (TimeFormatError, TypeError):
        return None


def _shown(value: Any, width: int = 60) -> str:
    text = value if isinstance(value, str) else repr(value)
    return quote(text, width) if isinstance(value, str) else excerpt(text, (), width)
