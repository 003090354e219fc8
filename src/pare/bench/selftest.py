"""The self-test gate: every scenario must prove that it can be solved, that it cannot be faked, and that
its checks judge other solutions as they should.

Deterministic runs per scenario, through the same turn loop as a real run:

* ``oracle`` — the oracle user and the oracle assistant: must succeed, with no failed oracle call and no
  failed scheduled event, every reactive event must fire, and none may answer with its ``otherwise``
  branch (the correction for a wrong question);
* ``slow_user`` — the same with a user that takes a harmless extra step before each of its steps and
  before answering: must still succeed within the turn limit (the scenario leaves slack);
* ``busy_user`` — the same with a user that never waits: between and after its steps it keeps doing
  something harmless on the phone. Must still succeed, with every reactive event the oracle sets off
  delivered: the scenario's timeline reaches its end whatever the user does (the clock does not wait
  on an idle user; replies due after the last turn arrive before the checks);
* ``nothing`` — a silent user and a silent assistant: must fail;
* ``user_alone`` — the oracle user's own steps with a silent assistant: must fail;
* ``by_hand`` — the user doing the task through the screens (``oracle.by_hand``) with a silent
  assistant: must fail, since the assistant's work is what is judged;
* ``unrelated`` — the oracle user and an assistant that proposes and does something unrelated: must fail;
* ``variant:<id>`` — each declared variant, played like the oracle: must get its declared verdict (at
  least one correct-but-different variant that passes, and two near-misses that fail); a variant that
  must pass and does, but that the world answered with an ``otherwise`` branch, breaches unless its
  ``otherwise_ok`` says why that correction is part of the solution.

Every run is judged with side effects (:mod:`pare.scenarios.side_effects`) against the envelope of the
gate's own oracle and passing-variant runs, which is kept for the runs to come, and with invented details
(:mod:`pare.scenarios.invented`). The fixed runs that must
fail must fail their goals: a side effect does not stand in for checks that prove nothing.

With mutants on, the gate also plays the mutants and rewrites of :mod:`pare.scenarios.mutants`, judged
like the variants (side effects included): a mutant must fail unless the scenario declares it equivalent
(``equivalent_mutants``), a rewrite must pass. Their verdicts are reported as the library's mutation score,
and a surviving mutant or a failing rewrite is a breach like a misjudged variant.

Warnings do not fail the gate: a reactive reply that restates what the assistant was meant to find, a
text a goal looks for in the assistant's work that no screen of the user's shows
(:mod:`pare.scenarios.user_reach`), an ``otherwise_ok`` that the variant's run never needed and, given a
judge model, a triggering text that a reactive event's rule and the judge read apart. Listed apart, and
not failing the gate either: the emails and messages of the oracle and passing variants that no judge
check reads, through which a false text to that person would pass, the text fields they write into items
that no check reads, and the reactive events that decide on free text by a rule alone
(:mod:`pare.scenarios.unjudged`).
"""

from __future__ import annotations

import asyncio
import time
from collections.abc import Awaitable, Callable, Collection, Iterable, Iterator, Mapping, Sequence
from dataclasses import dataclass, field, replace
from typing import Any, Literal, TypeVar

from pare.agents.policy import AssistantPolicy, SilentAssistant, SilentUser, UserPolicy
from pare.bench.envelope import envelope_solutions, expected_envelope, remember
from pare.bench.episode import EpisodeResult, EpisodeSettings, arun_episode
from pare.bench.reactions import WorldEvent, corrected_solution, unused_excuses, world_events
from pare.errors import UserInputError
from pare.scenarios.build import disagreements
from pare.scenarios.checks import Judge, JudgeVerdict
from pare.scenarios.invented import describe_all
from pare.scenarios.matchers import compile_matcher, reads_text
from pare.scenarios.model import Scenario, Solution
from pare.scenarios.mutants import mutants as generated_mutants
from pare.scenarios.mutants import rewrites as generated_rewrites
from pare.scenarios.oracle import BusyUser, OracleAssistant, OracleUser, SlowUser, UnrelatedAssistant
from pare.scenarios.side_effects import Envelope
from pare.scenarios.stats import FREE_TEXT_FIELDS
from pare.scenarios.unjudged import unjudged_events, unread_fields, unread_sends
from pare.scenarios.user_reach import unseen_facts

T = TypeVar("T")

PolicyPair = Callable[[Scenario], tuple[UserPolicy, AssistantPolicy]]

RUNS: dict[str, tuple[PolicyPair, bool]] = {
    "oracle": (lambda s: (OracleUser(s), OracleAssistant(s)), True),
    "slow_user": (lambda s: (SlowUser(s), OracleAssistant(s)), True),
    "busy_user": (lambda s: (BusyUser(s), OracleAssistant(s)), True),
    "nothing": (lambda s: (SilentUser(), SilentAssistant()), False),
    "user_alone": (lambda s: (OracleUser(s), SilentAssistant()), False),
    "by_hand": (lambda s: (OracleUser(s, s.by_hand()), SilentAssistant()), False),
    "unrelated": (lambda s: (OracleUser(s), UnrelatedAssistant(s)), False),
}
"""The fixed self-test runs: how to make their two policies, and whether the scenario must succeed."""

NO_PROPOSAL_RUNS = ("oracle", "slow_user", "busy_user", "unrelated")
"""The runs of a scenario where the right move is not to propose: the watchful silent assistant (the
oracle's, which has nothing to propose) must pass, also with a slow or a busy user, and an eager one must
fail. Doing nothing, the user alone and the user by hand are the oracle itself there."""

MIN_PASSING_VARIANTS = 1
MIN_FAILING_VARIANTS = 2
_SOLUTION_RUNS = ("oracle", "slow_user", "busy_user")
"""Runs that play a solution as written: every call they make must succeed."""
_REACTION_RUNS = ("oracle", "busy_user")
"""Runs in which every reactive event must fire: the oracle's (a trigger that cannot match is an
authoring error) and the busy user's (the world's replies must not depend on the user idling)."""


@dataclass(frozen=True, slots=True)
class RunVerdict:
    """One self-test run of one scenario."""

    run: str
    expected_success: bool
    success: bool | None
    """``None`` when the run could not be played at all."""
    problems: tuple[str, ...] = ()
    turns: int | None = None
    """Turns the run used (``None`` when it could not be played)."""
    why: str = ""
    """For a variant: why its declared verdict is right."""
    events: tuple[WorldEvent, ...] = ()
    """The scenario's events that fired in the run, each reactive one with the branch it took."""
    warnings: tuple[str, ...] = ()
    """What does not fail the run but should be looked at (an ``otherwise_ok`` the run never needed)."""
    after_last_turn: tuple[str, ...] = ()
    """The events the world delivered after the run's last turn (replies set off by then)."""

    @property
    def ok(self) -> bool:
        """Whether the run went as the gate demands."""
        return not self.problems and self.success == self.expected_success


MutantOutcome = Literal["killed", "declared", "survived", "stillborn", "passed", "failed"]
"""A mutant's verdict (killed: the checks failed it; declared: it passed and the scenario says why that is
right; survived: it passed and nothing says why; stillborn: it passed because the app refused a call the
oracle makes successfully, or, for a proposal moved earlier, because the event it no longer waits for came
first anyway, so the mutant changed nothing, and it is not counted), or a rewrite's (passed, as it must,
or failed)."""


@dataclass(frozen=True, slots=True)
class MutantVerdict:
    """One generated mutant or rewrite, played and judged."""

    name: str
    expect: Literal["fail", "pass"]
    what: str
    outcome: MutantOutcome
    detail: str = ""
    """Why: the first failed check or side effect, the reason it is declared, or why it could not run."""

    @property
    def ok(self) -> bool:
        """Whether the checks judged it as they must (a declared mutant counts as judged)."""
        return self.outcome in ("killed", "declared", "passed")


@dataclass(frozen=True, slots=True)
class ScenarioVerdict:
    """The gate's verdict on one scenario."""

    scenario_id: str
    runs: tuple[RunVerdict, ...]
    seconds: float
    details: dict[str, EpisodeResult] = field(default_factory=dict, compare=False, repr=False)
    problems: tuple[str, ...] = ()
    """Breaches that belong to no single run (too few variants)."""
    warnings: tuple[str, ...] = ()
    mutants: tuple[MutantVerdict, ...] = ()
    """The mutants and rewrites played (with mutants on), mutants first."""
    unread_sends: tuple[str, ...] = ()
    """The emails and messages of the oracle and passing variants that no judge check reads
    (:mod:`pare.scenarios.unjudged`): the envelope would let a false text to those people pass. A breach,
    as are the two below: what a solution writes, a check must read."""
    unjudged_events: tuple[str, ...] = ()
    """The reactive events that decide on free text by their rule alone, with no ``judge`` criterion."""
    unread_fields: tuple[str, ...] = ()
    """The text fields the oracle and passing variants write into items that no check reads."""

    @property
    def ok(self) -> bool:
        """Whether every run went as demanded, and every mutant and rewrite played was judged as it must."""
        return (
            not self.problems
            and all(run.ok for run in self.runs)
            and not self.misjudged_mutants
            and not self.unread
        )

    @property
    def unread(self) -> tuple[str, ...]:
        """What a solution writes that no check reads: messages, events' free text, items' text fields."""
        return (
            *(f"unread send {line}" for line in self.unread_sends),
            *(f"unjudged event {line}" for line in self.unjudged_events),
            *(f"unread field {line}" for line in self.unread_fields),
        )

    @property
    def misjudged_mutants(self) -> list[MutantVerdict]:
        """The surviving mutants and failing rewrites (a stillborn mutant changed nothing and is not one)."""
        return [mutant for mutant in self.mutants if mutant.outcome in ("survived", "failed")]

    def run(self, name: str) -> RunVerdict:
        """The run called ``name``."""
        return next(run for run in self.runs if run.run == name)

    def breaches(self) -> list[str]:
        """One line per broken demand."""
        lines = [f"{self.scenario_id}: {problem}" for problem in self.problems]
        for run in self.runs:
            if not run.ok:
                lines.extend(_run_breaches(self.scenario_id, run))
        lines.extend(_mutant_breach(self.scenario_id, mutant) for mutant in self.misjudged_mutants)
        lines.extend(f"{self.scenario_id}: {line}" for line in self.unread)
        return lines


def check_scenario(
    scenario: Scenario,
    settings: EpisodeSettings | None = None,
    *,
    runs: Collection[str] | None = None,
    variants: bool = True,
    judge: Judge | None = None,
    mutants: bool = False,
) -> ScenarioVerdict:
    """Run every self-test run (or only ``runs``) and every declared variant (unless ``variants`` is
    false) on ``scenario``; with ``mutants``, its generated mutants and rewrites too. The runs read text by
    the rules; with ``judge`` (a judge model), the warnings also name each triggering action whose text a
    reactive event's rule and the judge read apart.
    """
    began = time.perf_counter()
    verdicts = []
    details: dict[str, EpisodeResult] = {}
    plays: list[tuple[str, PolicyPair, bool, str]] = [
        (name, make, expected, "")
        for name, (make, expected) in RUNS.items()
        if (scenario.kind == "proposal" or name in NO_PROPOSAL_RUNS) and (runs is None or name in runs)
    ]
    fails: dict[str, list[str]] = {}
    excused: dict[str, frozenset[str]] = {}
    for variant in scenario.variants if variants else ():
        pair = _playing(scenario.solution(variant.id))
        plays.append((f"variant:{variant.id}", pair, variant.expect == "pass", variant.why))
        fails[f"variant:{variant.id}"] = variant.fails
        excused[f"variant:{variant.id}"] = frozenset(variant.otherwise_ok)
    users: dict[str, UserPolicy] = {}
    broken: dict[str, str] = {}
    with asyncio.Runner() as runner:  # one event loop for the scenario's runs, not one per run
        for name, make, _, _ in plays:
            user, assistant = make(scenario)
            played: list[EpisodeResult] = []
            # side effects are judged below, against the envelope these very runs give
            episode = arun_episode(
                scenario, user, assistant, _settings_for(name, scenario, settings), side_effects=False
            )
            try:
                runner.run(_kept(episode, played))
            except UserInputError as error:
                broken[name] = str(error)
                continue
            details[name], users[name] = played[0], user
        envelope = _envelope(scenario, details, settings, runner)
        played_mutants = tuple(_mutant_verdicts(scenario, settings, runner, envelope)) if mutants else ()
        apart: list[list[str]] = []
        if judge is not None:  # the judge is awaited in this loop too
            runner.run(_kept(_readings_apart(scenario, details, judge), apart))
    solutions = {"oracle" if name is None else f"variant:{name}" for name in envelope_solutions(scenario)}
    unread: list[str] = []
    unread_items: list[str] = []
    for name, _, expected, why in plays:
        if name in broken:
            verdicts.append(RunVerdict(name, expected, None, (broken[name],), why=why))
            continue
        result = details[name]
        result.outcome = result.outcome.with_side_effects(
            envelope.unexpected(result.changes, scenario.change_allowances())
        ).with_invented(result.invented)
        verdict = _verdict(name, scenario, users[name], result, expected, why, fails.get(name, []))
        verdicts.append(_with_reactions(verdict, scenario, result, excused.get(name, frozenset())))
        if name in solutions:  # what a solution tells a person widens the envelope: a check must read it
            final = result.env.snapshot(shared=True)
            log = result.env.log.entries
            unread.extend(f"[{name}] {line}" for line in unread_sends(scenario, log, final))
            unread_items.extend(f"[{name}] {line}" for line in unread_fields(scenario, log))
    warnings = [
        *restated_answers(scenario),
        *(fact.warning() for fact in unseen_facts(scenario)),
        *(line for run in verdicts for line in run.warnings),
    ]
    warnings.extend(line for lines in apart for line in lines)
    return ScenarioVerdict(
        scenario.id,
        tuple(verdicts),
        time.perf_counter() - began,
        details,
        tuple(_declaration_problems(scenario)),
        (*warnings, *_stale_declarations(scenario, played_mutants, mutants=mutants)),
        played_mutants,
        tuple(unread),
        tuple(unjudged_events(scenario)),
        tuple(unread_items),
    )


def _mutant_verdicts(
    scenario: Scenario, settings: EpisodeSettings | None, runner: asyncio.Runner, envelope: Envelope
) -> Iterator[MutantVerdict]:
    """Each generated mutant and rewrite of ``scenario``, played by the oracle policies and judged with
    side effects against ``envelope``.
    """
    for mutant in [*generated_mutants(scenario), *generated_rewrites(scenario)]:
        user, assistant = _playing(mutant.solution)(scenario)
        played: list[EpisodeResult] = []
        try:
            runner.run(_kept(arun_episode(scenario, user, assistant, settings, side_effects=False), played))
        except UserInputError as error:  # a mutant whose calls cannot even be made is no solution
            outcome: MutantOutcome = "failed" if mutant.is_rewrite else "killed"
            yield MutantVerdict(mutant.name, mutant.expect, mutant.what, outcome, f"could not run: {error}")
            continue
        result = played[0]
        side_effects = envelope.unexpected(result.changes, scenario.change_allowances())
        outcome_ = result.outcome.with_side_effects(side_effects).with_invented(result.invented)
        reasons = [
            *(f"check failed: {check.goal}[{check.index}] {check.detail}" for check in outcome_.failures()),
            *(f"side effect: {change.describe()}" for change in side_effects),
            *describe_all(result.invented),
        ]
        why = reasons[0] if reasons else ""
        if mutant.is_rewrite:
            verdict: MutantOutcome = "passed" if outcome_.success else "failed"
        elif not outcome_.success:
            verdict = "killed"
        elif refused := _refused_calls(result):
            verdict, why = "stillborn", f"the app refused {refused[0]}"
        elif mutant.waits_for is not None and _came_first(result, *mutant.waits_for):
            verdict, why = "stillborn", f"event '{mutant.waits_for[0]}' came before the proposal anyway"
        else:
            reason = scenario.equivalent_mutants.get(mutant.name)
            verdict, why = ("survived", "") if reason is None else ("declared", reason)
        yield MutantVerdict(mutant.name, mutant.expect, mutant.what, verdict, why)


def _came_first(result: EpisodeResult, event_id: str, proposal: str) -> bool:
    """Whether event ``event_id`` fired in ``result`` before the assistant made ``proposal``."""
    for entry in result.env.log:
        if entry.event_id == event_id:
            return True
        if entry.actor == "assistant" and entry.args.get("content") == proposal:
            return False
    return False


def _refused_calls(result: EpisodeResult) -> list[str]:
    """The assistant's calls that failed in ``result`` (the oracle's never do: the gate demands it)."""
    return [
        f"{entry.app}.{entry.tool}: {entry.error}"
        for entry in result.env.log
        if entry.actor == "assistant" and not entry.ok and not entry.injected_failure
    ]


def _stale_declarations(
    scenario: Scenario, played: Sequence[MutantVerdict], *, mutants: bool
) -> Iterator[str]:
    """Declared equivalent mutants that the generator no longer makes, or that the checks now kill."""
    if not mutants:
        return
    outcomes = {verdict.name: verdict.outcome for verdict in played}
    for name in scenario.equivalent_mutants:
        if name not in outcomes:
            yield f"equivalent_mutants names '{name}', which is not generated for this scenario"
        elif outcomes[name] == "killed":
            yield f"equivalent_mutants declares '{name}', which the checks kill: drop the declaration"


def _with_reactions(
    verdict: RunVerdict, scenario: Scenario, result: EpisodeResult, excused: frozenset[str]
) -> RunVerdict:
    """``verdict`` with the events that fired, and a breach where the world corrected a solution that
    had to succeed and did: the oracle always, a variant unless its ``otherwise_ok`` says why.
    """
    events = world_events(scenario, result.env)
    problems = list(verdict.problems)
    warnings: list[str] = []
    passing_variant = verdict.run.startswith("variant:") and verdict.expected_success and result.success
    if verdict.run == "oracle" or passing_variant:
        problems.extend(corrected_solution(scenario, verdict.run, events, excused))
    if excused:
        warnings.extend(unused_excuses(verdict.run, excused, events))
    late = result.after_last_turn.delivered if result.after_last_turn is not None else ()
    return replace(
        verdict, problems=tuple(problems), events=events, warnings=tuple(warnings), after_last_turn=late
    )


async def _readings_apart(scenario: Scenario, played: Mapping[str, EpisodeResult], judge: Judge) -> list[str]:
    """Where a reactive event's rule and the judge read a triggering text apart, in the runs ``played``:
    once per event and text (the oracle and the slow user write the same), each text judged once.
    """
    verdicts: dict[tuple[str, str, tuple[str, ...]], JudgeVerdict] = {}

    async def remembered(criterion: str, text: str, facts: Sequence[str] = ()) -> JudgeVerdict:
        key = (criterion, text, tuple(facts))
        if key not in verdicts:
            verdicts[key] = await judge(criterion, text, facts)
        return verdicts[key]

    seen: set[tuple[str, str]] = set()
    lines = []
    for name, result in played.items():
        for found in await disagreements(scenario, result.env.log.entries, remembered):
            if (found.event_id, found.text) not in seen:
                seen.add((found.event_id, found.text))
                lines.append(f"[{name}] {found.describe()}")
    return lines


def _envelope(
    scenario: Scenario,
    played: Mapping[str, EpisodeResult],
    settings: EpisodeSettings | None,
    runner: asyncio.Runner,
) -> Envelope:
    """The changes ``scenario``'s solutions make: from the gate's own runs when it played all of them with
    the default settings (and kept for the runs to come), else as a run finds it.
    """
    names = ["oracle" if name is None else f"variant:{name}" for name in envelope_solutions(scenario)]
    if (settings is None or settings == EpisodeSettings()) and all(name in played for name in names):
        return remember(scenario, [played[name].changes for name in names])
    found: list[Envelope] = []
    try:
        runner.run(_kept(expected_envelope(scenario), found))
    except UserInputError:  # a solution that cannot be played breaches its own run; the rest still judge
        return Envelope.of(played[name].changes for name in names if name in played)
    return found[0]


async def _kept(episode: Awaitable[T], into: list[T]) -> None:
    """Play ``episode`` and keep its result in ``into`` rather than return it: asyncio formats what a
    run returned when it puts back the Ctrl-C handler (``signal.getsignal`` reprs the handler, which
    holds the task), and the repr of a whole episode costs more than playing a short one.
    """
    into.append(await episode)


def _verdict(
    name: str,
    scenario: Scenario,
    user: UserPolicy,
    result: EpisodeResult,
    expected: bool,
    why: str,
    fails: list[str],
) -> RunVerdict:
    """The verdict on one played run: what went wrong, and whether it succeeded as demanded."""
    problems = _problems(name, scenario, result)
    scripted = name in ("by_hand", "oracle") or name.startswith("variant:")
    # a scripted step that never came tested nothing (a "wait" with nothing to come ends the episode)
    if scripted and type(user) is OracleUser and user.position < len(user.steps):
        problems.append(
            f"{name} played {user.position} of its {len(user.steps)} user steps: step "
            f"#{user.position + 1} ({user.steps[user.position].tool}) never came (its 'when' never held, or "
            "the episode ended first)"
        )
    met = {goal.id for goal in result.outcome.goals if goal.passed}
    success = result.success
    if not expected and not name.startswith("variant:"):
        # the runs that must fail prove the checks: a side effect of the unrelated assistant's does not
        # make up for checks that an unrelated task meets
        success = len(met) == len(result.outcome.goals)
    problems.extend(
        f"goal '{goal_id}' should fail ({why}) but was met" for goal_id in fails if goal_id in met
    )
    if "side_effects" in fails and not result.outcome.side_effects:
        problems.append(f"it should make a side effect ({why}) but made none")
    if "invented_details" in fails and not result.outcome.invented:
        problems.append(f"it should state a detail nothing gives ({why}) but stated none")
    if expected and not result.success:
        problems.extend(
            f"check failed: {check.goal}[{check.index}] {check.detail}" for check in result.outcome.failures()
        )
        problems.extend(f"side effect: {change.describe()}" for change in result.outcome.side_effects)
        problems.extend(describe_all(result.outcome.invented))
    return RunVerdict(name, expected, success, tuple(problems), result.turns, why)


def oracle_breaches(scenario: Scenario) -> list[str]:
    """What is wrong with ``scenario``'s oracle run: a failed call, a reaction that never fired, a goal
    it does not meet. Empty when the oracle passes, as the gate demands.
    """
    verdict = check_scenario(scenario, runs=("oracle",), variants=False)
    return [line for run in verdict.runs if not run.ok for line in _run_breaches(scenario.id, run)]


def _mutant_breach(scenario_id: str, mutant: MutantVerdict) -> str:
    """The breach line of a surviving mutant (the checks accepted a wrong solution) or a failing rewrite
    (they refused a right one).
    """
    if mutant.expect == "fail":
        return (
            f"{scenario_id}: mutant {mutant.name} ({mutant.what}) passes the checks: tighten them, or "
            "declare it in equivalent_mutants with the reason it is right"
        )
    why = f": {mutant.detail}" if mutant.detail else ""
    return f"{scenario_id}: rewrite {mutant.name} ({mutant.what}) fails the checks{why}"


def _run_breaches(scenario_id: str, run: RunVerdict) -> list[str]:
    if run.problems:
        return [f"{scenario_id} [{run.run}]: {problem}" for problem in run.problems]
    wanted = "succeed" if run.expected_success else "fail"
    reason = f" ({run.why})" if run.why else ""
    return [f"{scenario_id} [{run.run}]: should {wanted} but did not{reason}"]


def _settings_for(name: str, scenario: Scenario, settings: EpisodeSettings | None) -> EpisodeSettings | None:
    """The by-hand user is given turns enough for every one of its steps: the run must show that the
    user's own complete work is not credited to the assistant, not that the user ran out of time.
    """
    if name != "by_hand":
        return settings
    base = settings or EpisodeSettings()
    return base.model_copy(update={"max_turns": base.max_turns + len(scenario.by_hand().user)})


def _playing(solution: Solution) -> PolicyPair:
    """The oracle policies playing ``solution``."""
    return lambda scenario: (OracleUser(scenario, solution), OracleAssistant(scenario, solution))


def _problems(name: str, scenario: Scenario, result: EpisodeResult) -> list[str]:
    if name in _SOLUTION_RUNS or name.startswith("variant:"):
        problems = _solution_problems(
            result, proposing=bool(scenario.solution(_variant_id(name)).interventions)
        )
        if name in _REACTION_RUNS:
            problems.extend(_unfired_reactions(scenario, name, result))
        return problems
    if name == "by_hand":
        return [
            f"by_hand user call #{entry.index} {entry.app}.{entry.tool} failed: {entry.error}"
            for entry in result.env.log
            if entry.actor == "user" and not entry.ok
        ]
    return []


def _variant_id(run: str) -> str | None:
    return run.removeprefix("variant:") if run.startswith("variant:") else None


def _solution_problems(result: EpisodeResult, *, proposing: bool) -> list[str]:
    """A solution played as written must run cleanly: every call succeeds, every proposal is accepted."""
    problems = []
    for entry in result.env.log:
        if entry.actor in ("user", "assistant") and not entry.ok and not entry.injected_failure:
            problems.append(
                f"{entry.actor} call #{entry.index} {entry.app}.{entry.tool} failed: {entry.error}"
            )
    problems.extend(
        f"scheduled event '{entry.event_id}' failed: {entry.error}" for entry in result.env.failed_events()
    )
    proposals = result.env.agent_ui.state.proposals
    if proposing and not proposals:
        problems.append("the assistant never proposed (its intervention's condition never held)")
    problems.extend(
        f"proposal {p.proposal_id} ended {p.status}, not accepted"
        for p in proposals
        if p.status != "accepted"
    )
    return problems


def _unfired_reactions(scenario: Scenario, run: str, result: EpisodeResult) -> list[str]:
    """Reactive events that never fired: in the oracle run a trigger that cannot match is a silent
    authoring error; in the busy user's, a reply set off but never delivered.
    """
    scheduler = result.env.scheduler
    problems = []
    for event in scenario.events:
        if event.when is None or event.id in scheduler.completed:
            continue
        if event.id in scheduler.set_off:
            problems.append(f"reactive event '{event.id}' was set off in the {run} run but never delivered")
        else:
            problems.append(
                f"reactive event '{event.id}' never fired in the {run} run: its 'when' "
                + ("or 'if_args' " if event.if_args else "")
                + "matched none of the oracle's actions"
            )
    return problems


def _declaration_problems(scenario: Scenario) -> Iterator[str]:
    passing = sum(variant.expect == "pass" for variant in scenario.variants)
    failing = len(scenario.variants) - passing
    if passing < MIN_PASSING_VARIANTS:
        yield (
            f"declares {passing} passing variant(s); at least {MIN_PASSING_VARIANTS} correct-but-different "
            "solution (another valid tool, order, wording or artefact) is required"
        )
    if failing < MIN_FAILING_VARIANTS:
        yield (
            f"declares {failing} failing variant(s); at least {MIN_FAILING_VARIANTS} tempting near-misses "
            "(wrong person, day or item, a reply that declines, extra items) are required"
        )
    if scenario.kind == "proposal" and not scenario.oracle.by_hand:
        yield "declares no oracle.by_hand steps: how the user would do the task alone through the screens"


# -- warnings ---------------------------------------------------------------------------------------
def restated_answers(scenario: Scenario) -> Iterator[str]:
    """Reactive events that fire on any matching action and say what a goal looks for in the assistant's
    work: a wrong question would get the right answer anyway.
    """
    sought = list(_sought_texts(scenario))
    for event in scenario.events:
        if event.when is None or event.if_args:
            continue
        text = " ".join(_strings([value for key, value in event.args.items() if key in FREE_TEXT_FIELDS]))
        for goal_id, raw in sought:
            matcher = compile_matcher(raw)
            if text and matcher.test(text, scenario.start):
                yield (
                    f"reactive event '{event.id}' fires on any matching action and its text meets what goal "
                    f"'{goal_id}' looks for ({matcher.describe()}): a wrong question would be answered "
                    "with the right answer; condition it on what was written (if_args) or do not restate it"
                )
                break


def _sought_texts(scenario: Scenario) -> Iterator[tuple[str, Any]]:
    """Text matchers on free-text fields of the goals' positive checks on the assistant's work."""
    for goal in scenario.goals:
        for check in goal.checks:
            if check.action is not None and check.action.actor == "assistant":
                raws: Iterable[tuple[str, Any]] = check.action.args.items()
            elif (
                check.state is not None and check.state.by == "assistant" and not _forbids(check.state.count)
            ):
                raws = check.state.where.items()
            else:
                continue
            for name, raw in raws:
                if name in FREE_TEXT_FIELDS and _reads_text(raw):
                    yield goal.id, raw


def _forbids(count: Any) -> bool:
    return count == 0 or getattr(count, "max", None) == 0


def _reads_text(raw: Any) -> bool:
    return isinstance(raw, Mapping) and bool(raw) and all(reads_text(str(key)) for key in raw)


def _strings(value: Any) -> Iterator[str]:
    if isinstance(value, str):
        yield value
    elif isinstance(value, Mapping):
        for item in value.values():
            yield from _strings(item)
    elif isinstance(value, list):
        for item in value:
            yield from _strings(item)


def check_scenarios(
    scenarios: Iterable[Scenario], settings: EpisodeSettings | None = None
) -> list[ScenarioVerdict]:
    """The gate over several scenarios."""
    return [check_scenario(scenario, settings) for scenario in scenarios]
