"""Trying a matcher on a sentence (``pare scenarios match``): the verdict, why, and how the text was read.

An author writing a check wants to know, before running the gate, whether a wording passes and what the
reader made of it: the clauses the text was cut into and which of them are negated.
"""

from __future__ import annotations

from dataclasses import dataclass
from datetime import datetime
from typing import Any

from pare.scenarios import meaning
from pare.scenarios.excerpts import quote
from pare.scenarios.explain import explain
from pare.scenarios.kinds import matcher_problems
from pare.scenarios.loader import ScenarioError
from pare.scenarios.matchers import Matcher, MatcherError, compile_matcher
from pare.scenarios.problem_groups import LocatedProblem
from pare.yaml_source import YamlSyntaxError, parse_yaml

RULE_SOURCE = "RULE"
"""How errors name the rule given on the command line (where the loader names a file)."""


def parse_rule(text: str) -> Matcher:
    """The matcher written in ``text`` (YAML or JSON, as in a scenario file) for a text field.

    Raises:
        ScenarioError: the rule is not valid YAML, misspells an operator, or cannot be compiled; every
            problem is listed with its place, as the loader lists a file's.
    """
    try:
        document = parse_yaml(text)
    except YamlSyntaxError as error:
        line = error.line if "\n" in text.strip() else None  # a rule on one line: no line to name
        raise ScenarioError(RULE_SOURCE, [LocatedProblem(RULE_SOURCE, line, "(rule)", str(error))]) from None
    raw: Any = document.data
    problems = [
        LocatedProblem(RULE_SOURCE, None, ".".join(place) or "(rule)", message)
        for place, message in matcher_problems(raw, str)
    ]
    if not problems:
        try:
            return compile_matcher(raw)
        except MatcherError as error:
            problems.append(LocatedProblem(RULE_SOURCE, None, "(rule)", str(error)))
    raise ScenarioError(RULE_SOURCE, problems)


@dataclass(frozen=True, slots=True)
class Trial:
    """A matcher tried on a text."""

    passed: bool
    lines: tuple[str, ...]
    """What to show: the rule, the text, its clauses with their negations, and the verdict with why."""


def try_matcher(matcher: Matcher, text: str, start: datetime) -> Trial:
    """Try ``matcher`` on ``text`` as a check on a free-text field would (relative days and times
    resolved against ``start``), and say how the text was read.
    """
    passed = matcher.test(text, start)
    lines = [
        f"rule:  {matcher.describe()}",
        f"text:  {quote(text, 200)}",
        f"start: {start.isoformat()} ({start:%A})",
        "clauses (cut at sentence ends, emoji, commas, semicolons, 'but', 'instead of', ...):",
    ]
    negations = []
    for number, clause in enumerate(meaning.clauses(text), start=1):
        cue = meaning.negation_cue(clause)
        lines.append(f"  {number}. {quote(clause, 200)}" + (f"  negated by '{cue}'" if cue else ""))
        if cue:
            negations.append(f"'{cue}' in clause {number}")
    if len(lines) == 4:
        lines.append("  (none: the text is empty)")
    lines.append(f"negations: {', '.join(negations) if negations else 'none'}")
    lines.append("PASS" if passed else f"FAIL: {explain(matcher, text, start)}")
    return Trial(passed, tuple(lines))
