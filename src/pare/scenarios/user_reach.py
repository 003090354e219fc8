"""Facts the user is asked to take on trust: text a goal looks for that no screen of the user's ever shows.

A proposal is worth accepting when the user can check it. The details a correct solution must carry (the
address a cab goes to, the number put on a card, the name in a reply) are what a goal's checks look for
in the assistant's work; when such a detail is in the world only where the user cannot look (a document's
text in Files, which has no screens, the cab's distance table, a discount code no message announces, or
only the story), the user can only accept it on trust. This module finds those details.

The rule is static: the text the user can reach is every text value of the seed data of the apps with
screens (not the contents of Files documents, only their paths; not the cab's ``known_distances`` or the
shop's ``discount_codes``, which no screen lists) and every text argument of the scenario's events (what
arrives on the phone, a reaction included), what the user writes in the scenario's own steps (a card
they save by hand, a message they send: they know what they wrote), with the phone's own words (its apps'
titles and the descriptions of what their screens offer). A goal's text is *reachable* when one such
value, or the values of one record or collection read together (an email, a contact, a listing), meets
the check's matcher.
Only the plain word operators are read (``contains``, ``contains_any``, and ``any_of`` over them): they
name words that must be copied from somewhere, while times, counts and meanings (``mentions_day``,
``declines``...) are worked out rather than copied. It is a warning, not a breach: words that are the
assistant's own wording rather than a fact (none in the library) would be flagged too when the phone never
uses them.
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator, Mapping
from dataclasses import dataclass
from typing import Any

from pare.apps.registry import get_app_class
from pare.scenarios.matchers import compile_matcher
from pare.scenarios.model import Check, Scenario

WORD_OPERATORS = frozenset({"contains", "contains_any"})
"""The operators whose strings are words to be copied from the world."""
_COMBINING = frozenset({"any_of"})
UNSEEN_DATA: Mapping[str, frozenset[str]] = {
    "cab": frozenset({"known_distances"}),
    "shopping": frozenset({"discount_codes"}),
}
"""Seed collections no screen of the user's shows: the cab's distance table (only fares and durations
reach a screen) and the shop's codes (a code is typed at checkout, never listed)."""
NO_SCREENS = frozenset({"files"})
"""Apps without screens: only the paths of their documents reach the user, through attach pickers."""


@dataclass(frozen=True, slots=True)
class UnseenFact:
    """A text a goal looks for that the user cannot find on any screen."""

    goal: str
    check: int
    """The check's index in its goal (0-based)."""
    field: str
    matcher: str
    """The matcher, as it describes itself."""

    def warning(self) -> str:
        """The line the gate prints for it."""
        return (
            f"goal '{self.goal}' check {self.check + 1} looks for {self.matcher} in the assistant's "
            f"'{self.field}', but no text the user can reach meets it (seed data of apps with screens, "
            "event arguments): the user can only take it on trust; put the fact where the user can look "
            "(a message, a note, a contact, a listing), unless these words are the assistant's own wording "
            "rather than a fact"
        )


def reachable_texts(scenario: Scenario) -> list[str]:
    """Every text the user's screens can show: each text value, and each record's texts read together."""
    texts: list[str] = []
    for app, data in scenario.seed.items():
        if app in NO_SCREENS:
            texts.extend(_document_paths(data))
            continue
        hidden = UNSEEN_DATA.get(app, frozenset())
        if isinstance(data, Mapping):
            data = {key: value for key, value in data.items() if key not in hidden}
        _collect(data, texts)
    for step in scenario.oracle.user:  # what the user typed, they know
        _collect(step.args, texts)
    for event in scenario.events:
        _collect(event.args, texts)
        if event.otherwise is not None:
            _collect(event.otherwise.args, texts)
    texts.extend(_screen_words(scenario.apps))
    return texts


def _screen_words(apps: Iterable[str]) -> Iterator[str]:
    """The phone's own words: each app's title and description, its screens' titles and the summaries of
    what can be done on them (a cab app says "ride" and "driver" whatever the scenario holds).
    """
    for name in apps:
        app = get_app_class(name)
        yield f"{app.title}\n{app.description}"
        for screen in app.screens:
            yield "\n".join([screen.title, *(spec.summary for spec in screen.actions.values())])


def unseen_facts(scenario: Scenario) -> Iterator[UnseenFact]:
    """The texts the goals look for in the assistant's work that no reachable text meets."""
    texts = reachable_texts(scenario)
    for goal in scenario.goals:
        for index, check in enumerate(goal.checks):
            for field, raw in _sought_words(check):
                matcher = compile_matcher(raw)
                if not any(matcher.test(text, scenario.start) for text in texts):
                    yield UnseenFact(goal.id, index, field, matcher.describe())


def _sought_words(check: Check) -> Iterator[tuple[str, Any]]:
    """(field, matcher) pairs of word matchers in a positive check on the assistant's work."""
    if check.action is not None and check.action.actor == "assistant":
        fields: Mapping[str, Any] = check.action.args
    elif check.state is not None and check.state.by == "assistant" and not _forbids(check.state.count):
        fields = check.state.where
    elif check.judge is not None and check.judge.action.actor == "assistant":
        fields = {check.judge.field: check.judge.fallback}
    else:
        return
    yield from _word_fields(fields)


def _word_fields(fields: Mapping[str, Any]) -> Iterator[tuple[str, Any]]:
    for name, raw in fields.items():
        if name == "any_of" and isinstance(raw, list):
            # alternatives: one met is enough, so words are sought only when every alternative seeks some
            groups = [list(_word_fields(item)) if isinstance(item, Mapping) else [] for item in raw]
            if groups and all(groups):
                names = " or ".join(dict.fromkeys(name for group in groups for name, _ in group))
                yield names, {"any_of": [_all_of(group) for group in groups]}
        else:
            words = _words(raw)
            if words is not None:
                yield name, words


def _all_of(group: list[tuple[str, Any]]) -> Any:
    """One alternative's word matchers as one matcher (a record's joined text must meet them all)."""
    merged: dict[str, Any] = {}
    for _, raw in group:
        for key, value in raw.items():
            if key in merged:  # two fields ask for words with the same operator: keep both as alternatives
                return {"any_of": [raw for _, raw in group]}
            merged[key] = value
    return merged


def _words(raw: Any) -> dict[str, Any] | None:
    """The word operators of ``raw`` (``any_of`` of them included), without what is not copied text (a
    negation, a time, a meaning); ``None`` when it seeks no words.
    """
    if not isinstance(raw, Mapping):
        return None
    kept: dict[str, Any] = {}
    for key, value in raw.items():
        if key in WORD_OPERATORS:
            kept[key] = value
        elif key in _COMBINING and isinstance(value, list):
            alternatives = [_words(item) for item in value]
            if alternatives and all(item is not None for item in alternatives):
                kept[key] = alternatives
    return kept or None


def _forbids(count: Any) -> bool:
    return count == 0 or getattr(count, "max", None) == 0


def _collect(value: Any, texts: list[str]) -> str:
    """Add every text under ``value`` and every record's texts joined; return ``value``'s joined text."""
    if isinstance(value, str):
        texts.append(value)
        return value
    if isinstance(value, int | float) and not isinstance(value, bool):
        shown = _number(value)
        texts.append(shown)
        return shown
    if isinstance(value, Mapping):
        parts = [_collect(item, texts) for item in value.values()]
    elif isinstance(value, list | tuple):
        parts = [_collect(item, texts) for item in value]
    else:
        return ""
    joined = "\n".join(part for part in parts if part)
    if joined and len(parts) > 1:
        texts.append(joined)
    return joined


def _number(value: float) -> str:
    """A number as screens write it: 1450.0 as "1450", 23.85 as "23.85", 7.5 as "7.5 7.50" (or money)."""
    if float(value).is_integer():
        return str(int(value))
    return f"{value} {value:.2f}" if round(value, 2) == value and f"{value}" != f"{value:.2f}" else str(value)


def _document_paths(data: Any) -> Iterable[str]:
    """The paths of the Files app's seed (its documents' text stays out of reach)."""
    if not isinstance(data, Mapping):
        return []
    files = data.get("files") or {}
    return [str(path) for path in files] if isinstance(files, Mapping) else []
