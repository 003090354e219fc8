"""The benchmark's numbers for one configuration, computed from its episode records (no I/O).

Everything here is derived from :class:`~pare.results.records.EpisodeRecord` lines only, so a run can be
re-scored from its store. The rules, in one place (each field's docstring repeats its own):

* Only *planned* episodes count: records whose ``(scenario_id, run)`` is not planned are ignored and
  counted in ``coverage.unplanned``.
* Only *complete* episodes are scored. A failed episode (provider down, cache miss, PARE bug) is missing
  coverage, never a failure of the model; it appears in ``coverage.failed`` with its reason.
* "± SE" numbers are :class:`Estimate` values: one value per run index r = 1..k, computed over the
  complete episodes of that run, then the mean of those values and their standard error (sample
  standard deviation with ddof=1 divided by sqrt(n)). A run index that has nothing to measure (no
  complete episode, no observe turn, no proposal, ...) is skipped, and ``n`` says how many runs counted.
  This is the paper's "± across 4 runs".
* ``pass_hat`` and ``pass_at`` give, for every k up to the runs planned, the unbiased estimators of the
  chance that k runs drawn without replacement from a scenario's complete runs all succeed (pass^k,
  C(c, k) / C(n, k)) or at least one does (pass@k, 1 - C(n - c, k) / C(n, k)), with n the scenario's
  complete runs and c its successes, averaged over the scenarios with at least k complete runs. At k = n
  they equal the paper's Success^k and Success@k.
"""

from __future__ import annotations

import math
import random
import statistics
from collections.abc import Callable, Iterable, Mapping, Sequence
from typing import Any

from pydantic import BaseModel, ConfigDict, Field

from pare.agents.models.ledger import RoleUsage
from pare.results.records import DECISIONS, FAULT_KINDS, RESOLUTIONS, EpisodeRecord

__all__ = [
    "TOTAL",
    "UNSPECIFIED",
    "Breakdowns",
    "ConfigurationMetrics",
    "Coverage",
    "Estimate",
    "FailedEpisode",
    "GroupMetrics",
    "MissingEpisode",
    "SimulatorFaultMetrics",
    "UsageSummary",
    "compute_metrics",
    "pass_at_k",
    "pass_hat_k",
]

TOTAL = "total"
"""The key of the usage summed over every role in :attr:`ConfigurationMetrics.usage`."""
UNSPECIFIED = "unspecified"
"""The difficulty breakdown's name for episodes whose scenario declares no difficulty."""

_FROZEN = ConfigDict(extra="forbid", frozen=True)


class Estimate(BaseModel):
    """A mean over per-run values and its standard error.

    ``mean`` is the mean of the ``n`` per-run values (``None`` when ``n == 0``); ``se`` is their sample
    standard deviation (ddof=1) divided by ``sqrt(n)`` (``None`` when ``n < 2``, where it is undefined).
    """

    model_config = _FROZEN

    mean: float | None = None
    se: float | None = None
    n: int = 0

    @classmethod
    def of(cls, values: Iterable[float]) -> Estimate:
        """The estimate over ``values`` (one per run)."""
        data = list(values)
        if not data:
            return cls(mean=None, se=None, n=0)
        mean = statistics.fmean(data)
        se = statistics.stdev(data) / math.sqrt(len(data)) if len(data) >= 2 else None
        return cls(mean=mean, se=se, n=len(data))


class UsageSummary(BaseModel):
    """Model usage of one role (or of every role, under ``"total"``) over the complete episodes.

    Sums are over the complete planned episodes only; calls made in failed episodes are not counted,
    so that per-episode numbers divide like with like. Per-episode numbers divide by *every* complete
    episode, including those in which the role made no call (a role used in few episodes is cheap per
    episode).
    """

    model_config = _FROZEN

    calls: int = 0
    cached_calls: int = Field(default=0, description="Calls replayed from the record/replay cache.")
    failed_calls: int = 0
    prompt_tokens: int = 0
    completion_tokens: int = 0
    total_tokens: int = Field(default=0, description="prompt_tokens + completion_tokens.")
    prompt_tokens_per_episode: float | None = Field(
        default=None, description="prompt_tokens / complete episodes; None without complete episodes."
    )
    completion_tokens_per_episode: float | None = Field(
        default=None, description="completion_tokens / complete episodes."
    )
    tokens_per_episode: float | None = Field(default=None, description="total_tokens / complete episodes.")
    cost_usd: float | None = Field(
        default=None, description="Total cost; None ('unknown') when any call is unpriced, never 0."
    )
    known_cost_usd: float = Field(default=0.0, description="Sum of the costs that are known.")
    unknown_cost_calls: int = Field(default=0, description="Calls whose cost is unknown.")
    cost_per_episode: float | None = Field(
        default=None, description="cost_usd / complete episodes; None when the cost is unknown."
    )
    cost_per_success: float | None = Field(
        default=None,
        description="cost_usd / successful complete episodes; None when the cost is unknown or nothing "
        "succeeded.",
    )
    cost: str = Field(default="$0.0000", description="The cost in words (RoleUsage.describe_cost()).")

    @classmethod
    def of(cls, usage: RoleUsage, *, episodes: int, successes: int) -> UsageSummary:
        """Summarise ``usage`` summed over ``episodes`` complete episodes, ``successes`` of them won."""
        cost = usage.cost_usd
        return cls(
            calls=usage.calls,
            cached_calls=usage.cached_calls,
            failed_calls=usage.failed_calls,
            prompt_tokens=usage.prompt_tokens,
            completion_tokens=usage.completion_tokens,
            total_tokens=usage.total_tokens,
            prompt_tokens_per_episode=_ratio(usage.prompt_tokens, episodes),
            completion_tokens_per_episode=_ratio(usage.completion_tokens, episodes),
            tokens_per_episode=_ratio(usage.total_tokens, episodes),
            cost_usd=cost,
            known_cost_usd=usage.known_cost_usd,
            unknown_cost_calls=usage.unknown_cost_calls,
            cost_per_episode=None if cost is None else _ratio(cost, episodes),
            cost_per_success=None if cost is None else _ratio(cost, successes),
            cost=usage.describe_cost(),
        )


class GroupMetrics(BaseModel):
    """Results restricted to the complete episodes whose record lists one app, tag or difficulty."""

    model_config = _FROZEN

    episodes: int = Field(description="Complete episodes in the group.")
    scenarios: int = Field(description="Distinct scenarios among those episodes.")
    success_rate: Estimate = Field(
        description="Per run r: mean success over the group's complete episodes of run r; Estimate across "
        "runs (runs without an episode of the group skipped)."
    )
    proposals: int = Field(description="Proposals made in the group's complete episodes.")
    proposal_rate: Estimate = Field(
        default_factory=Estimate,
        description="Per run r: proposals / turns over the group's complete episodes of run r; Estimate "
        "across runs.",
    )
    acceptance_rate: Estimate = Field(
        description="Per run r: accepted / proposals over the group's complete episodes of run r; "
        "Estimate across runs (runs without proposals skipped)."
    )


class Breakdowns(BaseModel):
    """Group results by app, by tag and by difficulty, each keyed by value and sorted by it.

    An episode counts toward every app and every tag its record lists (a scenario using email and
    calendar counts toward both), so groups overlap and their episodes do not sum to the total.
    """

    model_config = _FROZEN

    apps: dict[str, GroupMetrics] = Field(default_factory=dict)
    tags: dict[str, GroupMetrics] = Field(default_factory=dict)
    difficulty: dict[str, GroupMetrics] = Field(
        default_factory=dict, description=f"Episodes without a difficulty are under '{UNSPECIFIED}'."
    )
    kinds: dict[str, GroupMetrics] = Field(
        default_factory=dict,
        description="By scenario kind: 'proposal' (the right move is to propose) and 'no_proposal'; "
        f"records written before kinds were recorded are under '{UNSPECIFIED}'.",
    )


class FailedEpisode(BaseModel):
    """A planned episode whose record says it could not be run, and why."""

    model_config = _FROZEN

    scenario_id: str
    run: int
    kind: str = Field(description="The failure kind, or 'unknown' when the record gives none.")
    message: str


class MissingEpisode(BaseModel):
    """A planned episode with no record at all (never started, or the run was interrupted)."""

    model_config = _FROZEN

    scenario_id: str
    run: int


class Coverage(BaseModel):
    """How much of the planned work has a complete record."""

    model_config = _FROZEN

    planned: int = Field(description="Distinct planned (scenario, run) episodes.")
    complete: int = Field(description="Planned episodes with a complete record.")
    failed: list[FailedEpisode] = Field(default_factory=list, description="Sorted by scenario, run.")
    missing: list[MissingEpisode] = Field(default_factory=list, description="Sorted by scenario, run.")
    unplanned: int = Field(default=0, description="Records ignored because their key was not planned.")
    complete_share: float | None = Field(
        default=None, description="complete / planned; None if none planned."
    )

    @property
    def problems(self) -> int:
        """Planned episodes without a complete record (failed plus missing)."""
        return len(self.failed) + len(self.missing)


class SimulatorFaultMetrics(BaseModel):
    """How often the user simulator spoiled an episode on its own (see :mod:`pare.bench.simulator_faults`)."""

    model_config = _FROZEN

    episodes_with_fault: int = Field(default=0, description="Complete episodes with a simulator fault.")
    failures: int = Field(default=0, description="Complete episodes that failed.")
    failures_with_fault: int = Field(default=0, description="Of them, those with a simulator fault.")
    failure_fault_share: float | None = Field(
        default=None, description="failures_with_fault / failures; None without a failure."
    )
    success_rate_without_faults: Estimate = Field(
        default_factory=Estimate,
        description="Per run r: successes / complete episodes of run r without a simulator fault; "
        "Estimate across runs (runs with none skipped).",
    )
    episodes_without_fault: int = Field(default=0, description="Complete episodes without a simulator fault.")
    kinds: dict[str, int] = Field(
        default_factory=dict, description="Complete episodes with each kind of fault (one may have several)."
    )

    @classmethod
    def of(cls, complete: Sequence[EpisodeRecord], run_indices: Iterable[int]) -> SimulatorFaultMetrics:
        """The fault figures of ``complete`` episodes."""
        failures = [record for record in complete if not record.success]
        clean = [record for record in complete if not record.simulator_fault]
        return cls(
            episodes_with_fault=len(complete) - len(clean),
            failures=len(failures),
            failures_with_fault=sum(record.simulator_fault for record in failures),
            failure_fault_share=_share(record.simulator_fault for record in failures),
            success_rate_without_faults=_success_rate(clean, run_indices),
            episodes_without_fault=len(clean),
            kinds={
                kind: sum(any(f.kind == kind for f in record.simulator_faults) for record in complete)
                for kind in FAULT_KINDS
            },
        )


class ConfigurationMetrics(BaseModel):
    """Every number the reports show for one configuration (one model setup at one sweep point).

    JSON-serialisable with ``model_dump(mode="json")`` and read back with ``model_validate``.
    """

    model_config = _FROZEN

    label: str
    params: dict[str, Any] = Field(default_factory=dict, description="Free metadata, e.g. the sweep point.")
    protocol: str = Field(
        default="pare", description="The protocol preset the run played (its manifest's protocol.preset)."
    )
    protocol_overrides: dict[str, Any] = Field(
        default_factory=dict, description="The protocol settings the run changed from its preset's."
    )
    runs: int = Field(description="k, the runs planned per scenario.")
    scenarios: int = Field(description="Distinct planned scenarios.")
    episodes_planned: int
    episodes_complete: int
    successes: int = Field(description="Successful complete episodes.")
    scenarios_fully_covered: int = Field(
        description="Scenarios whose k runs (1..k) all have a complete record; Success@k and Success^k "
        "count only these."
    )
    success_at_k: float | None = Field(
        description="Share of fully covered scenarios with at least one success among their k runs; None "
        "when no scenario is fully covered."
    )
    success_all_k: float | None = Field(
        description="Share of fully covered scenarios that succeeded in all k runs (Success^k); None when "
        "no scenario is fully covered."
    )
    success_rate: Estimate = Field(
        description="Per run r: successes / complete episodes of run r; Estimate across runs."
    )
    success_rate_ci: tuple[float, float] | None = Field(
        description="Percentile bootstrap interval over scenarios: each scenario's value is its mean "
        "success over its complete runs; scenarios are resampled with replacement and the statistic is "
        "the mean over the resample. None without a complete episode."
    )
    confidence: float = Field(description="The confidence level of success_rate_ci.")
    bootstrap_samples: int
    goal_rate: Estimate = Field(
        description="Per run r: mean of the episodes' goal_rate (share of the user's goals achieved, the "
        "paper's R_Succeed over goals); Estimate across runs."
    )
    user_did_work_rate: Estimate = Field(
        description="Per run r: share of its complete episodes that failed because the user made by hand "
        "something a goal wanted from the assistant (counted as failures in the success rate); Estimate "
        "across runs."
    )
    user_did_work: int = Field(default=0, description="Complete episodes in which the user did the work.")
    side_effect_rate: Estimate = Field(
        default_factory=Estimate,
        description="Per run r: share of its complete episodes in which the assistant made a change no "
        "solution of the scenario makes (counted as failures in the success rate); Estimate across runs.",
    )
    side_effects: int = Field(
        default=0, description="Complete episodes with a side effect of the assistant's."
    )
    wrong_irreversible_actions: Estimate = Field(
        default_factory=Estimate,
        description="Per run r: the mean over its complete episodes of the assistant's wrong irreversible "
        "actions (calls of irreversible tools, such as a sent message or a deletion, that made a change no "
        "solution of the scenario makes); Estimate across runs. Records written before harm was recorded "
        "are left out.",
    )
    wrong_irreversible_total: int = Field(
        default=0, description="Wrong irreversible actions summed over the complete episodes."
    )
    irreversible_actions: Estimate = Field(
        default_factory=Estimate,
        description="Per run r: the mean over its complete episodes of the assistant's successful calls of "
        "irreversible tools, right or wrong; Estimate across runs (older records left out).",
    )
    proposal_rate: Estimate = Field(
        description="The paper's proposal rate, 'the proportion of turns in which the assistant proposed a "
        "task': per run r, proposals / turns summed over its complete episodes; runs without turns skipped."
    )
    observe_proposal_rate: Estimate = Field(
        default_factory=Estimate,
        description="Per run r: proposals / observe turns, summed over its complete episodes (share of the "
        "turns in which the assistant was watching, not executing, in which it proposed); runs without "
        "observe turns skipped.",
    )
    accept_reward: Estimate = Field(
        default_factory=Estimate,
        description="The paper's per-step reward R_Accept (+1 for each accepted proposal, -1 for each "
        "rejected one, 0 otherwise) summed over an episode: per run r, its mean over the run's complete "
        "episodes; Estimate across runs.",
    )
    pass_hat: dict[int, float | None] = Field(
        default_factory=dict,
        description="For k = 1..runs, the unbiased pass^k: the mean over scenarios with at least k complete "
        "runs of C(c, k) / C(n, k) (n complete runs, c successes); None when no scenario has k.",
    )
    pass_at: dict[int, float | None] = Field(
        default_factory=dict,
        description="For k = 1..runs, the unbiased pass@k: the mean over scenarios with at least k complete "
        "runs of 1 - C(n - c, k) / C(n, k); None when no scenario has k.",
    )
    flip_scenarios: int = Field(
        default=0,
        description="Scenarios with at least two complete runs whose verdicts differ (some succeed, some "
        "fail).",
    )
    flip_rate: float | None = Field(
        default=None,
        description="flip_scenarios / scenarios with at least two complete runs: how often the same "
        "configuration gets a different verdict on the same scenario; None without such a scenario.",
    )
    acceptance_rate: Estimate = Field(
        description="Per run r: accepted / proposals (accepted = resolution 'accepted', directly or after "
        "gathering context); runs without proposals skipped."
    )
    read_actions: Estimate = Field(
        description="Per run r: mean of the assistant's read-only tool calls per complete episode."
    )
    turns: Estimate = Field(description="Per run r: mean turns per complete episode.")
    proposals: int = Field(description="Proposals in the complete episodes.")
    accepted: int = Field(description="Of them, resolved 'accepted'.")
    proposals_per_episode: float | None = Field(description="proposals / complete episodes.")
    decisions: dict[str, Estimate] = Field(
        description="For each decision (accept, reject, gather_context, truncated): per run r, the share "
        "of run r's proposals with that decision; Estimate across runs (runs without proposals skipped)."
    )
    decision_counts: dict[str, int] = Field(description="Proposals per decision, over all runs.")
    gather_context_proposals: int = Field(description="Proposals whose decision was gather_context.")
    gather_context_resolution: dict[str, Estimate] = Field(
        description="For each resolution (accepted, rejected, expired, truncated): per run r, the share of "
        "run r's gather_context proposals that ended so; Estimate across runs (runs without any skipped)."
    )
    resolution_counts: dict[str, int] = Field(description="gather_context proposals per resolution.")
    usage: dict[str, UsageSummary] = Field(
        description="Per role (sorted), then 'total' over every role; complete episodes only."
    )
    breakdowns: Breakdowns
    coverage: Coverage
    format_errors: dict[str, int] = Field(
        description="Malformed model answers per role, summed over complete episodes."
    )
    failed_steps: dict[str, int] = Field(
        description="Steps whose action failed or was malformed, per role, summed over complete episodes."
    )
    ended: dict[str, int] = Field(description="Complete episodes per end reason (max_turns, idle, ...).")
    simulator: SimulatorFaultMetrics = Field(
        default_factory=SimulatorFaultMetrics,
        description="The user simulator's own faults: the share of failures it caused, and the success rate "
        "without the episodes it spoiled.",
    )


def compute_metrics(
    records: Sequence[EpisodeRecord],
    *,
    label: str,
    runs: int,
    planned: Sequence[tuple[str, int]],
    params: Mapping[str, Any] | None = None,
    bootstrap_samples: int = 2000,
    confidence: float = 0.95,
    seed: int = 0,
) -> ConfigurationMetrics:
    """Compute every metric of one configuration from its episode records.

    Args:
        records: At most one record per ``(scenario_id, run)`` (already de-duplicated), complete or failed.
        label: The configuration's name in reports.
        runs: k, the number of runs per scenario.
        planned: Every ``(scenario_id, run)`` the configuration should have, with run in 1..k.
        params: Free metadata copied into the result (e.g. the sweep point).
        bootstrap_samples: Resamples for the success-rate confidence interval.
        confidence: Level of that interval (0.95 gives the 2.5th and 97.5th percentiles).
        seed: Seed of the bootstrap's ``random.Random``, so the interval is reproducible.

    Raises:
        ValueError: On a planned run outside 1..k, two records with one key, or a bad bootstrap setting.
    """
    if runs < 1:
        raise ValueError(f"runs must be at least 1, got {runs}")
    if not 0 < confidence < 1:
        raise ValueError(f"confidence must be between 0 and 1, got {confidence}")
    if bootstrap_samples < 1:
        raise ValueError(f"bootstrap_samples must be at least 1, got {bootstrap_samples}")
    planned_keys = sorted(set(planned))
    for scenario_id, run in planned_keys:
        if not 1 <= run <= runs:
            raise ValueError(f"planned run {run} of {scenario_id!r} is outside 1..{runs}")
    planned_set = set(planned_keys)
    by_key: dict[tuple[str, int], EpisodeRecord] = {}
    unplanned = 0
    for record in records:
        if record.key not in planned_set:
            unplanned += 1
            continue
        if record.key in by_key:
            raise ValueError(f"two records for {record.key}: de-duplicate the records first")
        by_key[record.key] = record
    complete = [by_key[key] for key in planned_keys if key in by_key and by_key[key].complete]
    scenario_ids = sorted({scenario_id for scenario_id, _ in planned_keys})
    run_indices = range(1, runs + 1)

    fully_covered = _fully_covered(scenario_ids, run_indices, by_key)
    successes = sum(record.success for record in complete)
    proposals = [proposal for record in complete for proposal in record.proposals]
    gathered = [proposal for proposal in proposals if proposal.decision == "gather_context"]
    flips = _flips(complete)

    return ConfigurationMetrics(
        label=label,
        params=dict(params or {}),
        runs=runs,
        scenarios=len(scenario_ids),
        episodes_planned=len(planned_keys),
        episodes_complete=len(complete),
        successes=successes,
        scenarios_fully_covered=len(fully_covered),
        success_at_k=_share(any(outcomes) for outcomes in fully_covered.values()),
        success_all_k=_share(all(outcomes) for outcomes in fully_covered.values()),
        success_rate=_success_rate(complete, run_indices),
        success_rate_ci=_bootstrap_ci(
            complete, samples=bootstrap_samples, confidence=confidence, rng=random.Random(seed)
        ),
        confidence=confidence,
        bootstrap_samples=bootstrap_samples,
        goal_rate=_per_run(complete, run_indices, lambda group: _mean(r.goal_rate for r in group)),
        user_did_work_rate=_per_run(
            complete, run_indices, lambda group: _share(r.user_did_work for r in group)
        ),
        user_did_work=sum(record.user_did_work for record in complete),
        side_effect_rate=_per_run(
            complete, run_indices, lambda group: _share(r.side_effects > 0 for r in group)
        ),
        side_effects=sum(record.side_effects > 0 for record in complete),
        wrong_irreversible_actions=_per_episode(
            complete, run_indices, lambda r: r.wrong_irreversible_actions
        ),
        wrong_irreversible_total=sum(record.wrong_irreversible_actions or 0 for record in complete),
        irreversible_actions=_per_episode(complete, run_indices, lambda r: r.irreversible_actions),
        proposal_rate=_proposal_rate(complete, run_indices),
        observe_proposal_rate=_per_run(
            complete,
            run_indices,
            lambda group: _ratio(sum(len(r.proposals) for r in group), sum(r.observe_turns for r in group)),
        ),
        accept_reward=_per_run(complete, run_indices, lambda group: _mean(r.accept_reward for r in group)),
        pass_hat=_pass_estimates(complete, runs, pass_hat_k),
        pass_at=_pass_estimates(complete, runs, pass_at_k),
        flip_scenarios=flips[0],
        flip_rate=_ratio(flips[0], flips[1]),
        acceptance_rate=_acceptance_rate(complete, run_indices),
        read_actions=_per_run(complete, run_indices, lambda group: _mean(r.read_actions for r in group)),
        turns=_per_run(complete, run_indices, lambda group: _mean(r.turns for r in group)),
        proposals=len(proposals),
        accepted=sum(record.accepted for record in complete),
        proposals_per_episode=_ratio(len(proposals), len(complete)),
        decisions={
            decision: _per_run(complete, run_indices, _decision_share(decision)) for decision in DECISIONS
        },
        decision_counts={d: sum(p.decision == d for p in proposals) for d in DECISIONS},
        gather_context_proposals=len(gathered),
        gather_context_resolution={
            resolution: _per_run(complete, run_indices, _resolution_share(resolution))
            for resolution in RESOLUTIONS
        },
        resolution_counts={s: sum(p.resolution == s for p in gathered) for s in RESOLUTIONS},
        usage=_usage(complete, successes),
        breakdowns=Breakdowns(
            apps=_breakdown(complete, run_indices, lambda record: record.apps),
            tags=_breakdown(complete, run_indices, lambda record: record.tags),
            difficulty=_breakdown(complete, run_indices, lambda record: [record.difficulty or UNSPECIFIED]),
            kinds=_breakdown(complete, run_indices, lambda record: [record.kind or UNSPECIFIED]),
        ),
        coverage=_coverage(planned_keys, by_key, len(complete), unplanned),
        format_errors=_sum_counts(record.format_errors for record in complete),
        failed_steps=_sum_counts(record.failed_steps for record in complete),
        ended=_sum_counts({record.ended: 1} for record in complete),
        simulator=SimulatorFaultMetrics.of(complete, run_indices),
    )


def _ratio(numerator: float, denominator: float) -> float | None:
    """``numerator / denominator``, or ``None`` when there is nothing to divide by."""
    return numerator / denominator if denominator else None


def _mean(values: Iterable[float]) -> float | None:
    """The mean, or ``None`` for no values."""
    data = list(values)
    return statistics.fmean(data) if data else None


def _share(flags: Iterable[bool]) -> float | None:
    """The share of true flags, or ``None`` for no flags."""
    data = list(flags)
    return sum(data) / len(data) if data else None


def _per_run(
    complete: Sequence[EpisodeRecord],
    run_indices: Iterable[int],
    value: Callable[[list[EpisodeRecord]], float | None],
) -> Estimate:
    """The :class:`Estimate` of ``value`` computed on each run's complete episodes.

    A run whose episodes give ``None`` (nothing to measure) or that has no complete episode is skipped.
    """
    values: list[float] = []
    for run in run_indices:
        group = [record for record in complete if record.run == run]
        if not group:
            continue
        result = value(group)
        if result is not None:
            values.append(result)
    return Estimate.of(values)


def _per_episode(
    complete: Sequence[EpisodeRecord],
    run_indices: Iterable[int],
    count: Callable[[EpisodeRecord], int | None],
) -> Estimate:
    """Per run: the mean of ``count`` over the run's complete episodes that recorded it (``None``: a record
    written before it was); Estimate across runs.
    """
    return _per_run(
        complete, run_indices, lambda group: _mean(v for r in group if (v := count(r)) is not None)
    )


def _success_rate(complete: Sequence[EpisodeRecord], run_indices: Iterable[int]) -> Estimate:
    """Per run: successes / complete episodes of the run; Estimate across runs."""
    return _per_run(complete, run_indices, lambda group: _share(r.success for r in group))


def _proposal_rate(complete: Sequence[EpisodeRecord], run_indices: Iterable[int]) -> Estimate:
    """Per run: proposals / turns over the run's complete episodes (the paper's definition)."""
    return _per_run(
        complete,
        run_indices,
        lambda group: _ratio(sum(len(r.proposals) for r in group), sum(r.turns for r in group)),
    )


def pass_hat_k(n: int, c: int, k: int) -> float:
    """The unbiased estimate of pass^k from ``n`` runs with ``c`` successes: the chance that ``k`` runs
    drawn without replacement all succeed, C(c, k) / C(n, k).
    """
    _check_pass_arguments(n, c, k)
    return math.comb(c, k) / math.comb(n, k)


def pass_at_k(n: int, c: int, k: int) -> float:
    """The unbiased estimate of pass@k from ``n`` runs with ``c`` successes: the chance that at least one
    of ``k`` runs drawn without replacement succeeds, 1 - C(n - c, k) / C(n, k).
    """
    _check_pass_arguments(n, c, k)
    return 1 - math.comb(n - c, k) / math.comb(n, k)


def _check_pass_arguments(n: int, c: int, k: int) -> None:
    if not 0 <= c <= n or not 1 <= k <= n:
        raise ValueError(f"need 0 <= c <= n and 1 <= k <= n, got n={n}, c={c}, k={k}")


def _pass_estimates(
    complete: Sequence[EpisodeRecord], runs: int, estimator: Callable[[int, int, int], float]
) -> dict[int, float | None]:
    """For k = 1..runs, ``estimator`` averaged over the scenarios with at least k complete runs."""
    outcomes = _outcomes_by_scenario(complete)
    estimates: dict[int, float | None] = {}
    for k in range(1, runs + 1):
        values = [estimator(len(runs_), sum(runs_), k) for runs_ in outcomes.values() if len(runs_) >= k]
        estimates[k] = statistics.fmean(values) if values else None
    return estimates


def _flips(complete: Sequence[EpisodeRecord]) -> tuple[int, int]:
    """Scenarios whose complete runs disagree on the verdict, and scenarios with two complete runs or more."""
    repeated = [runs for runs in _outcomes_by_scenario(complete).values() if len(runs) >= 2]
    return sum(len(set(runs)) > 1 for runs in repeated), len(repeated)


def _outcomes_by_scenario(complete: Sequence[EpisodeRecord]) -> dict[str, list[bool]]:
    """Each scenario's verdicts over its complete runs, scenarios sorted."""
    outcomes: dict[str, list[bool]] = {}
    for record in complete:
        outcomes.setdefault(record.scenario_id, []).append(record.success)
    return dict(sorted(outcomes.items()))


def _acceptance_rate(complete: Sequence[EpisodeRecord], run_indices: Iterable[int]) -> Estimate:
    """Per run: accepted / proposals over the run's complete episodes; runs without proposals skipped."""
    return _per_run(
        complete,
        run_indices,
        lambda group: _ratio(sum(r.accepted for r in group), sum(len(r.proposals) for r in group)),
    )


def _decision_share(decision: str) -> Callable[[list[EpisodeRecord]], float | None]:
    """Share of a run's proposals with ``decision`` (``None`` when the run has no proposal)."""

    def share(group: list[EpisodeRecord]) -> float | None:
        return _share(p.decision == decision for r in group for p in r.proposals)

    return share


def _resolution_share(resolution: str) -> Callable[[list[EpisodeRecord]], float | None]:
    """Share of a run's gather_context proposals that ended in ``resolution`` (``None`` without any)."""

    def share(group: list[EpisodeRecord]) -> float | None:
        return _share(
            p.resolution == resolution for r in group for p in r.proposals if p.decision == "gather_context"
        )

    return share


def _fully_covered(
    scenario_ids: Sequence[str], run_indices: Iterable[int], by_key: Mapping[tuple[str, int], EpisodeRecord]
) -> dict[str, list[bool]]:
    """The success of each run 1..k, for the scenarios whose k runs all have a complete record.

    A scenario missing any run is left out rather than counted with fewer runs: with fewer runs
    Success@k would be biased down and Success^k up.
    """
    indices = list(run_indices)
    covered: dict[str, list[bool]] = {}
    for scenario_id in scenario_ids:
        found = [by_key.get((scenario_id, run)) for run in indices]
        if all(record is not None and record.complete for record in found):
            covered[scenario_id] = [record.success for record in found if record is not None]
    return covered


def _bootstrap_ci(
    complete: Sequence[EpisodeRecord], *, samples: int, confidence: float, rng: random.Random
) -> tuple[float, float] | None:
    """Percentile bootstrap interval of the success rate, resampling scenarios.

    Each scenario with a complete episode contributes its mean success over its complete runs. Each of
    ``samples`` resamples draws that many scenarios with replacement and takes the mean of their values;
    the bounds are the ``(1 - confidence) / 2`` and ``(1 + confidence) / 2`` quantiles of the resample
    means, linearly interpolated between order statistics (numpy's default "linear" method). Resampling
    scenarios rather than episodes keeps a scenario's runs together, since they are not independent.
    """
    outcomes: dict[str, list[bool]] = {}
    for record in complete:
        outcomes.setdefault(record.scenario_id, []).append(record.success)
    if not outcomes:
        return None
    values = [sum(runs) / len(runs) for _, runs in sorted(outcomes.items())]
    means = sorted(statistics.fmean(rng.choices(values, k=len(values))) for _ in range(samples))
    tail = (1 - confidence) / 2
    return (_quantile(means, tail), _quantile(means, 1 - tail))


def _quantile(ordered: Sequence[float], q: float) -> float:
    """The ``q`` quantile of sorted values, interpolating linearly between neighbours."""
    position = q * (len(ordered) - 1)
    low = math.floor(position)
    high = min(low + 1, len(ordered) - 1)
    fraction = position - low
    return ordered[low] + (ordered[high] - ordered[low]) * fraction


def _usage(complete: Sequence[EpisodeRecord], successes: int) -> dict[str, UsageSummary]:
    """Usage summed per role over the complete episodes, roles sorted, then the total."""
    roles: dict[str, RoleUsage] = {}
    for record in complete:
        for role, usage in record.usage.items():
            roles[role] = roles.get(role, RoleUsage()) + usage
    total = RoleUsage()
    for usage in roles.values():
        total = total + usage
    episodes = len(complete)
    summary = {
        role: UsageSummary.of(usage, episodes=episodes, successes=successes)
        for role, usage in sorted(roles.items())
    }
    summary[TOTAL] = UsageSummary.of(total, episodes=episodes, successes=successes)
    return summary


def _breakdown(
    complete: Sequence[EpisodeRecord],
    run_indices: Iterable[int],
    values_of: Callable[[EpisodeRecord], Iterable[str]],
) -> dict[str, GroupMetrics]:
    """:class:`GroupMetrics` for every value ``values_of`` gives any complete episode, sorted by value."""
    groups: dict[str, list[EpisodeRecord]] = {}
    for record in complete:
        # a record listing a value twice still counts once toward it
        for value in dict.fromkeys(values_of(record)):
            groups.setdefault(value, []).append(record)
    indices = list(run_indices)
    return {
        value: GroupMetrics(
            episodes=len(group),
            scenarios=len({record.scenario_id for record in group}),
            success_rate=_success_rate(group, indices),
            proposals=sum(len(record.proposals) for record in group),
            proposal_rate=_proposal_rate(group, indices),
            acceptance_rate=_acceptance_rate(group, indices),
        )
        for value, group in sorted(groups.items())
    }


def _coverage(
    planned_keys: Sequence[tuple[str, int]],
    by_key: Mapping[tuple[str, int], EpisodeRecord],
    complete: int,
    unplanned: int,
) -> Coverage:
    """Which planned episodes failed, which have no record, and what share is complete."""
    failed: list[FailedEpisode] = []
    missing: list[MissingEpisode] = []
    for scenario_id, run in planned_keys:
        record = by_key.get((scenario_id, run))
        if record is None:
            missing.append(MissingEpisode(scenario_id=scenario_id, run=run))
        elif not record.complete:
            failure = record.failure
            failed.append(
                FailedEpisode(
                    scenario_id=scenario_id,
                    run=run,
                    kind=failure.kind if failure is not None else "unknown",
                    message=failure.message if failure is not None else "",
                )
            )
    return Coverage(
        planned=len(planned_keys),
        complete=complete,
        failed=failed,
        missing=missing,
        unplanned=unplanned,
        complete_share=_ratio(complete, len(planned_keys)),
    )


def _sum_counts(counts: Iterable[Mapping[str, int]]) -> dict[str, int]:
    """Add up per-name counts, sorted by name."""
    totals: dict[str, int] = {}
    for mapping in counts:
        for name, count in mapping.items():
            totals[name] = totals.get(name, 0) + count
    return dict(sorted(totals.items()))
