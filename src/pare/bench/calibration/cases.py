"""The cases of a user calibration: proposals whose right answer is known, each with the moment to make it.

A case is one proposal put to the user at the moment a solution of the scenario makes a proposal, with
the answer a person who wants what the scenario's user wants would give:

* ``oracle``: the oracle's own proposal (accept);
* ``variant``: a failing variant's proposal whose text differs from every right solution's (reject): the
  scenario's author wrote it as a wrong-but-plausible proposal (another day, another car, the return flight
  moved too), and it is made when that variant would make it;
* ``mutant``: the oracle's proposal with a generated near-miss carried into its text (reject): the person
  it names swapped for another of the seed, or a clock time an hour later
  (:mod:`pare.scenarios.mutants`); only mutants whose changed value the proposal spells out once are
  carried, so the text itself is wrong, not only what would be done;
* ``unrelated``: a plausible task that has nothing to do with the scenario
  (:class:`~pare.scenarios.oracle.UnrelatedAssistant`'s), made when the oracle would propose (reject);
* ``tempting``: in a scenario where the right move is not to propose, a failing variant's proposal (reject).

Cases are derived from the scenarios alone, deterministically: the same library gives the same cases,
in the same order, under the same ids (``<scenario>/<kind>:<name>``).
"""

from __future__ import annotations

import re
from collections.abc import Callable, Iterator, Mapping
from dataclasses import dataclass
from typing import Any, Literal

from pare.scenarios.model import Intervention, Scenario, Solution
from pare.scenarios.mutants import mutants
from pare.scenarios.oracle import UnrelatedAssistant

CaseKind = Literal["oracle", "variant", "mutant", "unrelated", "tempting"]
CASE_KINDS: tuple[CaseKind, ...] = ("oracle", "variant", "mutant", "unrelated", "tempting")
Expected = Literal["accept", "reject"]

CARRIED_OPERATORS = ("swap_person", "shift_time")
"""The mutant operators whose change a proposal's text can say: a person, a clock time. (A changed count
is not carried: a digit or a number word in a proposal is too often something else, "Stage 2", "Dev 3".)"""
PER_SCENARIO = 2
"""At most this many cases of one kind (variant, mutant, tempting) per scenario by default: the first ones."""

_CLOCK_VALUE = re.compile(r"(?:^|[ T])([01]?\d|2[0-3]):([0-5]\d)")


@dataclass(frozen=True, slots=True)
class CalibrationCase:
    """One proposal to put to the user, when, and the answer that is right."""

    scenario: Scenario
    kind: CaseKind
    name: str
    """Stable within the scenario: the variant's id, the mutant's name, ``oracle``, ``unrelated``."""
    expected: Expected
    proposal: str
    """The text put to the user."""
    solution: Solution
    """What the oracle plays up to the proposal (its user steps, the interventions before it)."""
    target: int
    """The index of the solution's intervention whose proposal is replaced by :attr:`proposal`."""
    what: str
    """What makes the proposal right or wrong, for reports."""

    @property
    def case_id(self) -> str:
        """``<scenario>/<kind>:<name>``: stable across runs of the library."""
        return f"{self.scenario.id}/{self.kind}:{self.name}"

    def identity(self) -> dict[str, Any]:
        """What the case plays: the identity a calibration folder compares when it resumes."""
        return {
            "id": self.case_id,
            "expected": self.expected,
            "proposal": self.proposal,
            "target": self.target,
        }


def calibration_cases(
    scenario: Scenario, *, kinds: tuple[CaseKind, ...] = CASE_KINDS, per_scenario: int = PER_SCENARIO
) -> list[CalibrationCase]:
    """The cases of ``scenario`` of the ``kinds`` asked, at most ``per_scenario`` variants, mutants and
    tempting proposals each.
    """
    makers = {
        "oracle": _oracle,
        "variant": _variants,
        "mutant": _mutants,
        "unrelated": _unrelated,
        "tempting": _tempting,
    }
    found: list[CalibrationCase] = []
    for kind in CASE_KINDS:
        if kind not in kinds:
            continue
        made = list(makers[kind](scenario))
        found.extend(made if kind in ("oracle", "unrelated") else made[:per_scenario])
    return found


def _right_proposals(scenario: Scenario) -> frozenset[str]:
    """The proposal texts of every right solution: the oracle and the passing variants."""
    passing = scenario.right_solutions()
    return frozenset(i.proposal for name in passing for i in scenario.solution(name).interventions)


def _oracle(scenario: Scenario) -> Iterator[CalibrationCase]:
    if scenario.kind != "proposal" or not scenario.oracle.interventions:
        return
    solution = scenario.solution()
    first = solution.interventions[0]
    yield CalibrationCase(scenario, "oracle", "oracle", "accept", first.proposal, solution, 0, "the oracle's")


def _unrelated(scenario: Scenario) -> Iterator[CalibrationCase]:
    if scenario.kind != "proposal" or not scenario.oracle.interventions:
        return
    text = UnrelatedAssistant(scenario).proposal
    yield CalibrationCase(
        scenario, "unrelated", "unrelated", "reject", text, scenario.solution(), 0, "unrelated to the goal"
    )


def _wrong_variant_proposals(scenario: Scenario) -> Iterator[tuple[str, Solution, int, str]]:
    """Each failing variant whose proposal text no right solution makes: its solution, the index of its
    first such proposal, and why it fails.
    """
    right = _right_proposals(scenario)
    for variant in scenario.variants:
        if variant.expect != "fail" or not variant.interventions:
            continue
        solution = scenario.solution(variant.id)
        target = next((k for k, i in enumerate(solution.interventions) if i.proposal not in right), None)
        if target is not None:
            yield variant.id, solution, target, variant.why


def _wrong_proposals(
    case_kind: CaseKind, scenario_kind: str
) -> Callable[[Scenario], Iterator[CalibrationCase]]:
    """The failing variants' proposals as cases to reject: ``variant`` cases in proposal scenarios,
    ``tempting`` ones (a proposal where none is right) in no-proposal scenarios.
    """

    def cases(scenario: Scenario) -> Iterator[CalibrationCase]:
        if scenario.kind != scenario_kind:
            return
        for name, solution, target, why in _wrong_variant_proposals(scenario):
            proposal = solution.interventions[target].proposal
            yield CalibrationCase(scenario, case_kind, name, "reject", proposal, solution, target, why)

    return cases


_variants = _wrong_proposals("variant", "proposal")
_tempting = _wrong_proposals("tempting", "no_proposal")


def _mutants(scenario: Scenario) -> Iterator[CalibrationCase]:
    if scenario.kind != "proposal":
        return
    oracle = scenario.solution()
    right = _right_proposals(scenario)
    names = _person_names(scenario.seed)
    for mutant in mutants(scenario):
        if mutant.operator not in CARRIED_OPERATORS:
            continue
        where = mutant.name.split(":")[1]
        i, j = (int(part) - 1 for part in where.split("."))
        before = oracle.interventions[i].actions[j].args
        after = mutant.solution.interventions[i].actions[j].args
        text = _carried(oracle.interventions[i].proposal, before, after, names)
        if text is None or text in right:
            continue
        interventions = (*oracle.interventions[:i], _with_proposal(oracle.interventions[i], text))
        solution = Solution(mutant.name, oracle.user, (*interventions, *oracle.interventions[i + 1 :]))
        yield CalibrationCase(scenario, "mutant", mutant.name, "reject", text, solution, i, mutant.what)


def _with_proposal(intervention: Intervention, text: str) -> Intervention:
    return intervention.model_copy(update={"proposal": text})


def _carried(
    proposal: str, before: Mapping[str, Any], after: Mapping[str, Any], names: Mapping[str, str]
) -> str | None:
    """``proposal`` with the change from ``before`` to ``after`` (an action's arguments) said in its words,
    or ``None`` when the proposal does not spell out the value that changed.
    """
    text = proposal
    for key in before:
        if before[key] == after.get(key):
            continue
        olds = before[key] if isinstance(before[key], list) else [before[key]]
        news = after[key] if isinstance(after.get(key), list) else [after.get(key)]
        for old, new in zip(olds, news, strict=False):
            if old != new:
                text = _replace_value(text, old, new, names)
    return text if text != proposal else None


def _replace_value(text: str, old: Any, new: Any, names: Mapping[str, str]) -> str:
    """``text`` with the first way it spells ``old`` (a person, a clock time) exactly once
    spelled as ``new`` (unchanged when it spells it no way, or more than once).
    """
    for old_form, new_form in _forms(old, new, names):
        pattern = re.compile(rf"(?<![\w:.]){re.escape(old_form)}(?![\w:])", re.IGNORECASE)
        if len(pattern.findall(text)) == 1:  # said once: what is said twice may be two things
            return pattern.sub(new_form, text)
    return text


def _forms(old: Any, new: Any, names: Mapping[str, str]) -> list[tuple[str, str]]:
    """The pairs of spellings to look for and write: a time's clock; a person's address (or id), full name
    and first name.
    """
    if not (isinstance(old, str) and isinstance(new, str)):
        return []
    old_clock, new_clock = _CLOCK_VALUE.search(old), _CLOCK_VALUE.search(new)
    if old_clock and new_clock and old_clock.group(0) != new_clock.group(0):
        return [(f"{int(old_clock[1]):02d}:{old_clock[2]}", f"{int(new_clock[1]):02d}:{new_clock[2]}")]
    pairs = [(old, new)]
    old_name, new_name = names.get(old.lower()), names.get(new.lower())
    if old_name and new_name:
        pairs.append((old_name, new_name))
        pairs.append((old_name.split()[0], new_name.split()[0]))
    return pairs


def _person_names(seed: Mapping[str, Mapping[str, Any]]) -> dict[str, str]:
    """Each person of the seed by every way a write may name them (address, messaging id, full name; all
    lower case) with their full name.
    """
    found: dict[str, str] = {}
    for contact in seed.get("contacts", {}).get("contacts", []) or []:
        if not isinstance(contact, Mapping) or not contact.get("first_name"):
            continue
        name = f"{contact['first_name']} {contact.get('last_name') or ''}".strip()
        found[name.lower()] = name
        for field in ("email", "phone"):
            if isinstance(contact.get(field), str):
                found[contact[field].lower()] = name
    users = seed.get("messaging", {}).get("users", {})
    if isinstance(users, Mapping):
        for user_id, name in users.items():
            if isinstance(name, str):
                found[str(user_id).lower()] = name
                found[name.lower()] = name
    return found
