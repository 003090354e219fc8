"""What the user simulator did wrong on its own: faults found in a finished episode from the scenario's
knowledge, so a score can be read without the episodes its simulated user spoiled.

Every rule is written to flag only what the scenario proves, never what a reader would have to guess: a
fault the rules miss leaves the episode counted as it is today, a false fault would hide an assistant's
failure. The rules, each with what proves it:

``accepted_wrong``
    The user accepted a proposal that contradicts its goal: the episode failed, the goals a failing
    variant is declared to fail did fail, and the proposal matches that variant's proposal (a near-miss
    the scenario declares wrong) and no proposal of the oracle or of a passing variant. An accepted
    proposal the scenario says nothing about (an unrelated offer, an eager one in a ``no_proposal``
    scenario, whose quiet goal fails on the proposal itself whatever the user answers) is not flagged:
    nothing proves the answer was wrong, or that it changed the verdict.
``rejected_right``
    The user rejected a proposal that matches the oracle's (or a passing variant's) and no failing
    variant's: the assistant offered what the scenario's own solution offers.
``did_by_hand``
    The episode failed with ``user_did_work`` (the user made by hand what a goal wanted from the
    assistant) and, after accepting a proposal, the user changed data in an app the oracle's
    interventions act on: the assistant had been told to do it.
``stalled``
    In a ``proposal`` scenario that failed, the user left a proposal matching a solution's unanswered
    until it expired, or until the episode ended after :data:`STALL_STEPS` steps of its own with it on
    screen; or no proposal was ever made because the user never took the step the solution's help waits
    for (an intervention's condition on a user action never held) and the user changed nothing by hand
    either (a user who did the task alone is no stall: doing it alone is no fault before accepting).
``unseen_fact``
    The user typed a fact-like value (an email address, or a token with :data:`FACT_DIGITS` digits or
    more that is not a time or a date) found nowhere in what it was shown before: its persona and goal,
    the views of the phone before each step, what each of its steps showed, and what the scenario itself
    has the user type (its oracle's, by-hand and variants' user steps and answers).

Proposals *match* when their words are alike (Jaccard similarity of their lower-case word sets at least
:data:`MATCH_SIMILARITY`) and they name the same figures (the same tokens with digits or ``@``): a
near-miss usually differs in one figure (a time, a count), which similar wording must not hide.
"""

from __future__ import annotations

import functools
import re
from collections.abc import Iterable, Iterator, Mapping, Sequence
from typing import TYPE_CHECKING, Any

from pare.agents.policy import WAIT
from pare.results.records import ProposalRecord, SimulatorFault
from pare.scenarios.leaves import leaves
from pare.scenarios.oracle import Conditions

if TYPE_CHECKING:
    from pare.bench.episode import EpisodeResult
    from pare.scenarios.model import Scenario

ACCEPT = "accept_proposal"
MATCH_SIMILARITY = 0.75
"""The least word overlap (Jaccard) for a proposal to match a solution's proposal."""
STALL_STEPS = 3
"""Steps a user may take with a proposal on screen before leaving it unanswered to the end is a stall."""
FACT_DIGITS = 3
"""Digits a typed token needs to count as a fact (a phone number, an amount, a code), not a word."""

_WORD = re.compile(r"[\w@.'+-]+")
_FIGURE = re.compile(r"[\w@.'+/:-]*[\d@][\w@.'+/:-]*")
"""A token holding a digit or ``@``; paths, addresses and times are kept whole (``/`` and ``:`` inside)."""
_EMAIL = re.compile(r"^[\w.+-]+@[\w-]+(\.[\w-]+)+$")
_TIME_OR_DATE = re.compile(
    r"^(\d{1,2}[:.h]\d{2}(:\d{2})?"
    r"|\d{4}-\d{2}-\d{2}(t\d{1,2}:\d{2}(:\d{2}(\.\d+)?)?)?(z|[+-]\d{2}:?\d{2})?"
    r"|\d{1,2}/\d{1,2}(/\d{2,4})?)$"
)
"""A date or a clock time, which a user works out rather than copies: never a fact, however many digits."""


def find_faults(
    scenario: Scenario, result: EpisodeResult, proposals: Sequence[ProposalRecord]
) -> list[SimulatorFault]:
    """Every fault of the user simulator in ``result`` (an episode of ``scenario`` whose proposals were
    classified as ``proposals``), in the order of the turns they happened in.
    """
    failed = not result.outcome.success
    # a scenario's variants are validated when first read, which costs: read them only when a rule needs them
    compared = proposals and (failed or any(p.resolution == "rejected" for p in proposals))
    passing, failing = _solution_proposals(scenario) if compared else ([], [])
    faults: list[SimulatorFault] = []
    faults += _decision_faults(scenario, proposals, passing, failing, result)
    if failed and result.outcome.user_did_work:
        faults += _work_after_accepting(scenario, result)
    if failed and scenario.kind == "proposal":
        faults += _stalls(scenario, result, proposals, passing, failing)
    faults += _unseen_facts(scenario, result)
    return sorted(faults, key=lambda fault: fault.turn)


# -- matching proposals ------------------------------------------------------------------------------------
@functools.lru_cache(maxsize=4096)
def words(text: str) -> frozenset[str]:
    """The lower-case words of ``text``, punctuation at their ends dropped."""
    found = (match.group(0).lower().strip(".'-+") for match in _WORD.finditer(text))
    return frozenset(word for word in found if word)


def _figures(tokens: frozenset[str]) -> frozenset[str]:
    return frozenset(token for token in tokens if "@" in token or any(char.isdigit() for char in token))


def matches(proposal: str, reference: str) -> bool:
    """Whether ``proposal`` says what ``reference`` says: alike in words, the same in figures."""
    left, right = words(proposal), words(reference)
    if not left or not right or _figures(left) != _figures(right):
        return False
    return len(left & right) / len(left | right) >= MATCH_SIMILARITY


def _solution_proposals(scenario: Scenario) -> tuple[list[str], list[tuple[str, list[str]]]]:
    """The proposals of the oracle and passing variants; the failing variants' (each with the goals it
    is declared to fail), those the oracle makes too left out (a variant may fail by its actions alone).
    """
    passing = [intervention.proposal for intervention in scenario.oracle.interventions]
    failing: list[tuple[str, list[str]]] = []
    for variant in scenario.variants:
        if variant.interventions is None:
            continue
        texts = [intervention.proposal for intervention in variant.interventions]
        if variant.teaches:
            passing += texts
        elif variant.expect == "fail":
            failing += [(text, variant.fails) for text in texts]
    failing = [(text, fails) for text, fails in failing if text not in passing]
    return passing, failing


def _decision_faults(
    scenario: Scenario,
    proposals: Sequence[ProposalRecord],
    passing: Sequence[str],
    failing: Sequence[tuple[str, list[str]]],
    result: EpisodeResult,
) -> Iterator[SimulatorFault]:
    failed_goals = {goal.id for goal in result.outcome.goals if not goal.passed}
    # what a near-miss may be declared to fail besides goals
    failed_goals |= {"side_effects"} if result.outcome.side_effects else set()
    failed_goals |= {"invented_details"} if result.outcome.invented else set()
    for proposal in proposals:
        turn = proposal.answered_turn or proposal.turn
        good = any(matches(proposal.content, text) for text in passing)
        bad = [fails for text, fails in failing if matches(proposal.content, text)]
        if proposal.resolution == "rejected" and good and not bad:
            yield SimulatorFault(
                kind="rejected_right",
                turn=turn,
                proposal_id=proposal.proposal_id,
                detail="rejected a proposal that matches the scenario's solution",
            )
        if proposal.resolution != "accepted" or result.outcome.success:
            continue
        if bad and not good and any(set(fails) <= failed_goals for fails in bad):
            yield SimulatorFault(
                kind="accepted_wrong",
                turn=turn,
                proposal_id=proposal.proposal_id,
                detail="accepted a proposal that matches a near-miss the scenario declares wrong",
            )


# -- doing the work, stalling ---------------------------------------------------------------------------
def _work_after_accepting(scenario: Scenario, result: EpisodeResult) -> Iterator[SimulatorFault]:
    task_apps = {action.tool.split("__")[0] for i in scenario.oracle.interventions for action in i.actions}
    log = result.env.log.entries
    accepted_at = next(
        (
            entry.index
            for entry in log
            if entry.actor == "user" and entry.tool == "accept_proposal" and entry.ok
        ),
        None,
    )
    if accepted_at is None:
        return
    for entry in log[accepted_at + 1 :]:
        if entry.actor == "user" and entry.kind == "write" and entry.ok and entry.app in task_apps:
            yield SimulatorFault(
                kind="did_by_hand",
                turn=entry.turn,
                detail=f"after accepting a proposal, did {entry.app} {entry.tool} by hand",
            )
            return


def _stalls(
    scenario: Scenario,
    result: EpisodeResult,
    proposals: Sequence[ProposalRecord],
    passing: Sequence[str],
    failing: Sequence[tuple[str, list[str]]],
) -> Iterator[SimulatorFault]:
    for proposal in proposals:
        worth_answering = any(matches(proposal.content, text) for text in passing) and not any(
            matches(proposal.content, text) for text, _ in failing
        )
        if not worth_answering:
            continue
        if proposal.resolution == "expired":
            yield SimulatorFault(
                kind="stalled",
                turn=proposal.turn,
                proposal_id=proposal.proposal_id,
                detail="left a proposal that matches the solution unanswered until it expired",
            )
        elif proposal.resolution == "truncated" and proposal.user_steps_before_answer >= STALL_STEPS:
            yield SimulatorFault(
                kind="stalled",
                turn=proposal.turn,
                proposal_id=proposal.proposal_id,
                detail=f"left a proposal that matches the solution unanswered through "
                f"{proposal.user_steps_before_answer} steps to the end",
            )
    if proposals or any(entry.actor == "user" and entry.kind == "write" for entry in result.env.log):
        return  # help was offered, or the user took the task in hand: not a stall
    conditions = Conditions(scenario, scenario.solution())
    env = result.env
    for intervention in scenario.oracle.interventions:
        when = intervention.when
        if when is None or when.action is None or when.action.actor != "user":
            continue
        if when.event is not None and when.event not in env.scheduler.completed:
            continue  # what it waits for never came: not the user's doing
        if not conditions.hold(when, env):
            waits = sum(step.actor == "user" and step.action.tool == WAIT for step in result.steps)
            yield SimulatorFault(
                kind="stalled",
                turn=result.turns,
                detail=f"never took the step the solution's help waits for ({_pattern_text(when.action)}); "
                f"waited {waits} of {result.turns} turns",
            )
            return


def _pattern_text(pattern: Any) -> str:
    tool = pattern.tool if isinstance(pattern.tool, str) else " or ".join(pattern.tool or [])
    return tool or pattern.app or "an action"


# -- facts never seen ------------------------------------------------------------------------------------
def _unseen_facts(scenario: Scenario, result: EpisodeResult) -> Iterator[SimulatorFault]:
    typed = [(step, typed_facts(step.action.args)) for step in result.steps if step.actor == "user"]
    if not any(facts for _, facts in typed):
        return  # nothing fact-like typed: nothing to look for (most episodes; the search costs)
    seen: set[str] = set()
    _learn(seen, [scenario.user.persona, scenario.user.goal])
    _learn(seen, list(_scripted_words(scenario)))  # the scenario's own words for the user are the user's
    for step, facts in typed:
        _learn(seen, [step.view])
        unseen = sorted(token for token in facts if not _known(token, seen))
        if unseen:
            yield SimulatorFault(
                kind="unseen_fact",
                turn=step.turn,
                detail=f"typed {', '.join(unseen)} in {step.action.tool}, shown nowhere before",
            )
            return  # one is proof enough; the rest would repeat it
        _learn(seen, [step.observation])


def _scripted_words(scenario: Scenario) -> Iterator[Any]:
    """What the scenario itself has the user type or say, in its oracle, by hand and in every variant."""
    steps = [*scenario.oracle.user, *scenario.oracle.by_hand]
    interventions = list(scenario.oracle.interventions)
    for variant in scenario.variants:
        steps += variant.user or []
        interventions += variant.interventions or []
    yield from (step.args for step in steps)
    yield from (intervention.answer for intervention in interventions)


def typed_facts(args: Mapping[str, Any]) -> set[str]:
    """The fact-like tokens typed in an action's arguments."""
    found = set()
    for text in _texts(args):
        for token in _figure_tokens(text):
            digits = sum(char.isdigit() for char in token)
            if _EMAIL.match(token) or (digits >= FACT_DIGITS and not _TIME_OR_DATE.match(token)):
                found.add(token)
    return found


def _figure_tokens(text: str) -> set[str]:
    """The lower-case tokens of ``text`` that hold a digit or ``@`` (the only ones a fact can be)."""
    found = (match.group(0).lower().strip(".'-+:/") for match in _FIGURE.finditer(text))
    return {token for token in found if token}


def _known(token: str, seen: set[str]) -> bool:
    if token in seen:
        return True
    digits = _digits(token)
    if "@" in token or not digits or any(char.isalpha() for char in token):
        return False
    return any(digits in known for known in seen if known.isdigit())  # a phone number without its prefix


def _digits(token: str) -> str:
    return "".join(char for char in token if char.isdigit())


def _learn(seen: set[str], values: Iterable[Any]) -> None:
    for value in values:
        for text in _texts(value):
            for token in _figure_tokens(text):
                seen.add(token)
                if not any(char.isalpha() for char in token):
                    seen.add(_digits(token))


def _texts(value: Any) -> Iterator[str]:
    """Every text in ``value`` (nested lists and mappings), numbers as they would be typed."""
    for _, leaf in leaves(value):
        if isinstance(leaf, str):
            yield leaf
        elif isinstance(leaf, int | float) and not isinstance(leaf, bool):
            yield str(leaf)
