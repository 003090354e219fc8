"""Every metric checked against numbers worked out by hand on a small set of records.

The fixture (k = 3 runs, planned: scenarios A, B, C x runs 1..3):

    scenario  apps              tags             difficulty
    A         email, calendar   reply            easy
    B         email             schedule         hard
    C         messaging         reply, schedule  hard

    key  status    success goal_rate observe_turns read turns proposals (decision/resolution)
    A1   complete  yes     1.0       5             10   10    accept/accepted
    A2   complete  no      0.5       4             15   10    reject/rejected, gather/accepted
    A3   complete  yes     1.0       5             30   10    gather/expired, truncated/truncated
    B1   complete  yes     1.0       5             20   10    accept/accepted, gather/truncated
    B2   complete  yes     1.0       6             25   6     accept/accepted
    B3   complete  yes     1.0       5             30   10    accept/accepted, gather/rejected
    C1   complete  no      0.5       5             0    10    (none)
    C2   failed (provider_unavailable: "provider down")
    C3   no record at all
    plus two unplanned records: D1 and A4 (ignored).
"""

from __future__ import annotations

import json
import math
from typing import Any

import pytest

from pare.agents.models.ledger import RoleUsage
from pare.results.metrics import ConfigurationMetrics, Estimate, compute_metrics, pass_at_k, pass_hat_k
from pare.results.records import EpisodeRecord, Failure, ProposalRecord
from pare.results.report import render_csv, render_markdown

APPS = {"A": ["email", "calendar"], "B": ["email"], "C": ["messaging"], "D": ["email"]}
TAGS = {"A": ["reply"], "B": ["schedule"], "C": ["reply", "schedule"], "D": []}
DIFFICULTY = {"A": "easy", "B": "hard", "C": "hard", "D": ""}


def usage(calls: int, prompt: int, completion: int, cost: float, unpriced: int = 0) -> RoleUsage:
    return RoleUsage(
        calls=calls,
        prompt_tokens=prompt,
        completion_tokens=completion,
        known_cost_usd=cost,
        unknown_cost_calls=unpriced,
    )


def standard_usage() -> dict[str, RoleUsage]:
    return {"user": usage(10, 1000, 100, 0.01), "observe": usage(5, 2000, 200, 0.02)}


def record(
    scenario: str,
    run: int,
    *,
    success: bool = False,
    goal_rate: float = 1.0,
    observe_turns: int = 5,
    proposals: tuple[tuple[str, str], ...] = (),
    read_actions: int = 0,
    turns: int = 10,
    ended: str = "max_turns",
    usage: dict[str, RoleUsage] | None = None,
    failure: Failure | None = None,
    **extra: Any,
) -> EpisodeRecord:
    """A record made by hand; ``proposals`` are (decision, resolution) pairs."""
    return EpisodeRecord(
        scenario_id=scenario,
        run=run,
        status="failed" if failure is not None else "complete",
        failure=failure,
        scenario_hash="h-" + scenario,
        seed=run,
        apps=APPS.get(scenario, []),
        tags=TAGS.get(scenario, []),
        difficulty=DIFFICULTY.get(scenario, ""),
        success=success,
        goal_rate=goal_rate,
        turns=turns,
        ended=ended,
        observe_turns=observe_turns,
        proposals=[
            ProposalRecord(
                proposal_id=f"{scenario}{run}-p{index}",
                turn=index + 1,
                content="Shall I?",
                decision=decision,
                resolution=resolution,
            )
            for index, (decision, resolution) in enumerate(proposals)
        ],
        read_actions=read_actions,
        usage=standard_usage() if usage is None else usage,
        **extra,
    )


ACC = ("accept", "accepted")
REJ = ("reject", "rejected")


def fixture_records() -> list[EpisodeRecord]:
    a1_usage = {**standard_usage(), "execute": usage(3, 600, 60, 0.006)}
    c1_usage = {**standard_usage(), "judge": usage(1, 500, 50, 0.0, unpriced=1)}
    return [
        record(
            "A",
            1,
            success=True,
            proposals=(ACC,),
            read_actions=10,
            usage=a1_usage,
            format_errors={"observe": 2},
        ),
        record(
            "A",
            2,
            goal_rate=0.5,
            observe_turns=4,
            proposals=(REJ, ("gather_context", "accepted")),
            read_actions=15,
            failed_steps={"execute": 1},
        ),
        record(
            "A",
            3,
            success=True,
            proposals=(("gather_context", "expired"), ("truncated", "truncated")),
            read_actions=30,
        ),
        record("B", 1, success=True, proposals=(ACC, ("gather_context", "truncated")), read_actions=20),
        record(
            "B",
            2,
            success=True,
            observe_turns=6,
            proposals=(ACC,),
            read_actions=25,
            turns=6,
            ended="idle",
            format_errors={"observe": 1, "user": 1},
        ),
        record("B", 3, success=True, proposals=(ACC, ("gather_context", "rejected")), read_actions=30),
        record("C", 1, goal_rate=0.5, read_actions=0, usage=c1_usage),
        record(
            "C",
            2,
            failure=Failure(kind="provider_unavailable", message="provider down"),
            usage={"user": usage(2, 100, 10, 0.5)},
        ),
        # unplanned: ignored everywhere except coverage.unplanned
        record("D", 1, success=True, proposals=(ACC,), usage={"user": usage(99, 9, 9, 9.0)}),
        record("A", 4, success=True, proposals=(ACC,)),
    ]


PLANNED = [(scenario, run) for scenario in "ABC" for run in (1, 2, 3)]


def se(values: list[float]) -> float:
    """Sample standard deviation (ddof=1) over sqrt(n), written out."""
    n = len(values)
    mean = sum(values) / n
    return math.sqrt(sum((v - mean) ** 2 for v in values) / (n - 1)) / math.sqrt(n)


def check(estimate: Estimate, values: list[float]) -> None:
    assert estimate.n == len(values)
    assert estimate.mean == pytest.approx(sum(values) / len(values))
    assert estimate.se == pytest.approx(se(values))


@pytest.fixture(scope="module")
def metrics() -> ConfigurationMetrics:
    return compute_metrics(
        fixture_records(), label="model-x", runs=3, planned=PLANNED, params={"assistant": "model-x"}
    )


def test_estimate_of() -> None:
    assert Estimate.of([]) == Estimate(mean=None, se=None, n=0)
    assert Estimate.of([0.25]) == Estimate(mean=0.25, se=None, n=1)
    # values 1, 2, 3: mean 2; deviations -1, 0, 1 -> sum of squares 2 / (n-1 = 2) = 1 -> sd 1 -> se 1/sqrt(3)
    estimate = Estimate.of([1, 2, 3])
    assert estimate.mean == 2
    assert estimate.se == pytest.approx(1 / math.sqrt(3))
    assert estimate.n == 3


def test_identity_and_counts(metrics: ConfigurationMetrics) -> None:
    assert metrics.label == "model-x"
    assert metrics.params == {"assistant": "model-x"}
    assert metrics.runs == 3
    assert metrics.scenarios == 3
    assert metrics.episodes_planned == 9
    # complete planned: A1 A2 A3 B1 B2 B3 C1
    assert metrics.episodes_complete == 7
    # successes: A1 A3 B1 B2 B3
    assert metrics.successes == 5


def test_success_at_k_and_success_all_k(metrics: ConfigurationMetrics) -> None:
    # C lacks C2 (failed) and C3 (missing): only A and B are fully covered
    assert metrics.scenarios_fully_covered == 2
    # A succeeded in runs 1 and 3, B in all three: both have >= 1 success -> 2/2
    assert metrics.success_at_k == 1.0
    # only B succeeded in all 3 runs -> 1/2 (counting C, whose only run failed, would give 1/3)
    assert metrics.success_all_k == 0.5


def test_success_at_k_none_without_full_coverage() -> None:
    metrics = compute_metrics([record("A", 1, success=True)], label="x", runs=2, planned=[("A", 1), ("A", 2)])
    assert metrics.scenarios_fully_covered == 0
    assert metrics.success_at_k is None
    assert metrics.success_all_k is None
    assert metrics.success_rate == Estimate(mean=1.0, se=None, n=1)


def test_success_rate_across_runs(metrics: ConfigurationMetrics) -> None:
    # run 1: A1 yes, B1 yes, C1 no -> 2/3; run 2: A2 no, B2 yes -> 1/2; run 3: A3 yes, B3 yes -> 1
    # mean (2/3 + 1/2 + 1) / 3 = 13/18; deviations -1/18, -4/18, 5/18 -> squares 42/324
    # / (n-1 = 2) = 21/324 -> / n = 7/324 -> se = sqrt(7)/18
    assert metrics.success_rate.n == 3
    assert metrics.success_rate.mean == pytest.approx(13 / 18)
    assert metrics.success_rate.se == pytest.approx(math.sqrt(7) / 18)


def test_goal_rate(metrics: ConfigurationMetrics) -> None:
    # run 1: (1 + 1 + 0.5) / 3 = 5/6; run 2: (0.5 + 1) / 2 = 3/4; run 3: (1 + 1) / 2 = 1 -> mean 31/36
    check(metrics.goal_rate, [5 / 6, 3 / 4, 1.0])
    assert metrics.goal_rate.mean == pytest.approx(31 / 36)


def test_proposal_rate_is_per_turn_as_in_the_paper(metrics: ConfigurationMetrics) -> None:
    # run 1: (1 + 2 + 0) proposals / (10 + 10 + 10) turns = 0.1
    # run 2: (2 + 1) / (10 + 6) = 0.1875; run 3: (2 + 2) / (10 + 10) = 0.2
    check(metrics.proposal_rate, [0.1, 0.1875, 0.2])
    assert metrics.proposal_rate.mean == pytest.approx(0.1625)


def test_observe_proposal_rate(metrics: ConfigurationMetrics) -> None:
    # run 1: (1 + 2 + 0) proposals / (5 + 5 + 5) observe turns = 0.2
    # run 2: (2 + 1) / (4 + 6) = 0.3; run 3: (2 + 2) / (5 + 5) = 0.4
    # mean 0.3; deviations -0.1, 0, 0.1 -> 0.02 / 2 = 0.01 -> se = sqrt(0.01 / 3)
    assert metrics.observe_proposal_rate.mean == pytest.approx(0.3)
    assert metrics.observe_proposal_rate.se == pytest.approx(math.sqrt(0.01 / 3))
    assert metrics.observe_proposal_rate.n == 3


def test_pass_hat_and_pass_at_for_every_k(metrics: ConfigurationMetrics) -> None:
    # complete runs: A 3 (2 successes), B 3 (3), C 1 (0)
    # pass^1 = mean(2/3, 1, 0) = 5/9; pass^2 over A, B = mean(C(2,2)/C(3,2) = 1/3, 1) = 2/3;
    # pass^3 = mean(0, 1) = 1/2 (the paper's Success^3)
    assert metrics.pass_hat == pytest.approx({1: 5 / 9, 2: 2 / 3, 3: 1 / 2})
    # pass@1 = pass^1; pass@2 for A = 1 - C(1,2)/C(3,2) = 1, B = 1; pass@3 = 1 (Success@3)
    assert metrics.pass_at == pytest.approx({1: 5 / 9, 2: 1.0, 3: 1.0})
    assert metrics.pass_hat[3] == metrics.success_all_k
    assert metrics.pass_at[3] == metrics.success_at_k


@pytest.mark.parametrize(
    ("n", "c", "k", "hat", "at"),
    [
        (4, 2, 1, 0.5, 0.5),
        (4, 2, 2, 1 / 6, 5 / 6),
        (4, 3, 3, 1 / 4, 1.0),
        (5, 0, 2, 0.0, 0.0),
        (5, 5, 5, 1, 1),
    ],
)
def test_unbiased_estimators(n: int, c: int, k: int, hat: float, at: float) -> None:
    # (4, 2, 2): C(2,2)/C(4,2) = 1/6; 1 - C(2,2)/C(4,2) = 5/6. (4, 3, 3): C(3,3)/C(4,3) = 1/4; C(1,3) = 0
    assert pass_hat_k(n, c, k) == pytest.approx(hat)
    assert pass_at_k(n, c, k) == pytest.approx(at)


def test_estimators_refuse_impossible_counts() -> None:
    with pytest.raises(ValueError, match="n=3, c=4"):
        pass_hat_k(3, 4, 1)
    with pytest.raises(ValueError, match="k=4"):
        pass_at_k(3, 1, 4)


def test_flips(metrics: ConfigurationMetrics) -> None:
    # A (yes, no, yes) flips, B (yes x3) does not; C has one complete run and does not count
    assert metrics.flip_scenarios == 1
    assert metrics.flip_rate == pytest.approx(0.5)


def test_accept_reward(metrics: ConfigurationMetrics) -> None:
    # per episode: A1 +1; A2 -1 +1 = 0; A3 0 (expired, truncated); B1 +1; B2 +1; B3 +1 -1 = 0; C1 0
    # run 1: (1 + 1 + 0) / 3; run 2: (0 + 1) / 2; run 3: (0 + 0) / 2
    check(metrics.accept_reward, [2 / 3, 1 / 2, 0.0])


def test_results_by_kind() -> None:
    records = [
        record("A", 1, success=True, proposals=(ACC,), kind="proposal"),
        record("A", 2, success=False, proposals=(REJ,), kind="proposal"),
        record("B", 1, success=True, kind="no_proposal"),
        record("B", 2, success=False, proposals=(REJ,), kind="no_proposal"),
    ]
    metrics = compute_metrics(records, label="m", runs=2, planned=[("A", 1), ("A", 2), ("B", 1), ("B", 2)])
    kinds = metrics.breakdowns.kinds
    assert sorted(kinds) == ["no_proposal", "proposal"]
    assert kinds["no_proposal"].success_rate.mean == pytest.approx(0.5)
    # run 1: no proposal in 10 turns; run 2: one in 10 turns
    assert kinds["no_proposal"].proposal_rate.mean == pytest.approx(0.05)
    assert kinds["proposal"].acceptance_rate.mean == pytest.approx(0.5)


def test_acceptance_rate(metrics: ConfigurationMetrics) -> None:
    # accepted resolutions: run 1: A1, B1's accept -> 2 of 3; run 2: A2's gather, B2 -> 2 of 3;
    # run 3: B3's accept -> 1 of 4. Mean (2/3 + 2/3 + 1/4) / 3 = 19/36
    check(metrics.acceptance_rate, [2 / 3, 2 / 3, 1 / 4])
    assert metrics.acceptance_rate.mean == pytest.approx(19 / 36)
    assert metrics.proposals == 10
    assert metrics.accepted == 5
    assert metrics.proposals_per_episode == pytest.approx(10 / 7)


def test_read_actions_and_turns(metrics: ConfigurationMetrics) -> None:
    # run 1: (10 + 20 + 0) / 3 = 10; run 2: (15 + 25) / 2 = 20; run 3: (30 + 30) / 2 = 30
    # mean 20; deviations -10, 0, 10 -> 200 / 2 = 100 -> se = sqrt(100 / 3)
    assert metrics.read_actions.mean == pytest.approx(20.0)
    assert metrics.read_actions.se == pytest.approx(math.sqrt(100 / 3))
    # turns: run 1: 10; run 2: (10 + 6) / 2 = 8; run 3: 10
    check(metrics.turns, [10.0, 8.0, 10.0])
    assert metrics.ended == {"idle": 1, "max_turns": 6}


def test_runs_without_observe_turns_or_proposals_are_skipped() -> None:
    records = [
        record("A", 1, observe_turns=0),  # nothing to divide by: run 1 is skipped for both rates
        record("A", 2, observe_turns=4, proposals=(ACC,)),  # 1/4 per observe turn, 1/1 accepted
        record("A", 3, observe_turns=5),  # 0/5 per observe turn; no proposal: skipped for acceptance
    ]
    metrics = compute_metrics(records, label="x", runs=3, planned=[("A", r) for r in (1, 2, 3)])
    check(metrics.observe_proposal_rate, [0.25, 0.0])
    check(metrics.proposal_rate, [0.0, 0.1, 0.0])  # per turn (10 each): run 1 counts
    assert metrics.acceptance_rate == Estimate(mean=1.0, se=None, n=1)
    assert metrics.decisions["accept"] == Estimate(mean=1.0, se=None, n=1)
    assert metrics.gather_context_resolution["accepted"] == Estimate(mean=None, se=None, n=0)


def test_decisions(metrics: ConfigurationMetrics) -> None:
    # run 1 (3 proposals): accept A1, accept B1, gather B1
    # run 2 (3): reject A2, gather A2, accept B2
    # run 3 (4): gather A3, truncated A3, accept B3, gather B3
    check(metrics.decisions["accept"], [2 / 3, 1 / 3, 1 / 4])
    check(metrics.decisions["reject"], [0.0, 1 / 3, 0.0])
    check(metrics.decisions["gather_context"], [1 / 3, 1 / 3, 1 / 2])
    check(metrics.decisions["truncated"], [0.0, 0.0, 1 / 4])
    assert list(metrics.decisions) == ["accept", "reject", "gather_context", "truncated"]
    assert metrics.decision_counts == {"accept": 4, "reject": 1, "gather_context": 4, "truncated": 1}


def test_gather_context_resolution(metrics: ConfigurationMetrics) -> None:
    # gather_context proposals: run 1: B1 -> truncated; run 2: A2 -> accepted;
    # run 3: A3 -> expired, B3 -> rejected
    check(metrics.gather_context_resolution["accepted"], [0.0, 1.0, 0.0])
    check(metrics.gather_context_resolution["rejected"], [0.0, 0.0, 0.5])
    check(metrics.gather_context_resolution["expired"], [0.0, 0.0, 0.5])
    check(metrics.gather_context_resolution["truncated"], [1.0, 0.0, 0.0])
    assert metrics.gather_context_proposals == 4
    assert metrics.resolution_counts == {"accepted": 1, "rejected": 1, "expired": 1, "truncated": 1}


def test_usage_per_role_and_total(metrics: ConfigurationMetrics) -> None:
    # only the 7 complete planned episodes count (C2's and the unplanned records' calls do not)
    assert list(metrics.usage) == ["execute", "judge", "observe", "user", "total"]
    user = metrics.usage["user"]
    # 7 episodes x (10 calls, 1000 prompt, 100 completion, $0.01)
    assert (user.calls, user.prompt_tokens, user.completion_tokens) == (70, 7000, 700)
    assert user.prompt_tokens_per_episode == pytest.approx(1000)
    assert user.completion_tokens_per_episode == pytest.approx(100)
    assert user.tokens_per_episode == pytest.approx(1100)
    assert user.cost_usd == pytest.approx(0.07)
    assert user.cost_per_episode == pytest.approx(0.01)
    assert user.cost_per_success == pytest.approx(0.07 / 5)  # 5 successes
    assert user.cost == "$0.0700"
    observe = metrics.usage["observe"]
    assert observe.cost_usd == pytest.approx(0.14)  # 7 x $0.02
    assert observe.cost_per_success == pytest.approx(0.028)
    execute = metrics.usage["execute"]  # A1 only, but per episode divides by all 7
    assert execute.calls == 3
    assert execute.prompt_tokens_per_episode == pytest.approx(600 / 7)
    assert execute.cost_per_episode == pytest.approx(0.006 / 7)
    judge = metrics.usage["judge"]  # C1's one unpriced call
    assert judge.cost_usd is None
    assert judge.cost_per_episode is None
    assert judge.cost_per_success is None
    assert judge.cost == "unknown (1 of 1 calls unpriced)"
    total = metrics.usage["total"]
    # calls 70 + 35 + 3 + 1 = 109; prompt 7000 + 14000 + 600 + 500 = 22100; completion 700 + 1400 + 60 + 50
    assert (total.calls, total.prompt_tokens, total.completion_tokens) == (109, 22100, 2210)
    assert total.total_tokens == 24310
    assert total.cost_usd is None  # one call unpriced: unknown, never 0
    assert total.known_cost_usd == pytest.approx(0.216)  # 0.07 + 0.14 + 0.006
    assert total.unknown_cost_calls == 1
    assert total.cost == "unknown (1 of 109 calls unpriced; $0.2160 known)"


def test_cost_per_success_none_without_success() -> None:
    metrics = compute_metrics([record("A", 1)], label="x", runs=1, planned=[("A", 1)])
    total = metrics.usage["total"]
    assert total.cost_usd == pytest.approx(0.03)
    assert total.cost_per_episode == pytest.approx(0.03)
    assert total.cost_per_success is None


def test_breakdown_by_app(metrics: ConfigurationMetrics) -> None:
    apps = metrics.breakdowns.apps
    assert list(apps) == ["calendar", "email", "messaging"]
    # email: A and B, 6 episodes; per run: 1 (A1, B1), 1/2 (A2 no, B2), 1 (A3, B3)
    # mean 5/6; deviations 1/6, -1/3, 1/6 -> 6/36 / 2 = 1/12 -> / 3 = 1/36 -> se 1/6
    email = apps["email"]
    assert (email.episodes, email.scenarios, email.proposals) == (6, 2, 10)
    assert email.success_rate.mean == pytest.approx(5 / 6)
    assert email.success_rate.se == pytest.approx(1 / 6)
    check(email.acceptance_rate, [2 / 3, 2 / 3, 1 / 4])  # C1 had no proposal: same as overall
    # calendar: A only; success 1, 0, 1 -> mean 2/3, se 1/3; accepted 1/1, 1/2, 0/2
    calendar = apps["calendar"]
    assert (calendar.episodes, calendar.scenarios, calendar.proposals) == (3, 1, 5)
    assert calendar.success_rate.mean == pytest.approx(2 / 3)
    assert calendar.success_rate.se == pytest.approx(1 / 3)
    check(calendar.acceptance_rate, [1.0, 0.5, 0.0])
    # messaging: C1 only -> one run, no se; no proposals -> no acceptance rate
    messaging = apps["messaging"]
    assert (messaging.episodes, messaging.scenarios) == (1, 1)
    assert messaging.success_rate == Estimate(mean=0.0, se=None, n=1)
    assert messaging.acceptance_rate == Estimate(mean=None, se=None, n=0)


def test_breakdown_by_tag_and_difficulty(metrics: ConfigurationMetrics) -> None:
    tags = metrics.breakdowns.tags
    assert list(tags) == ["reply", "schedule"]
    # reply: A and C (C1 counts toward both of its tags); run 1: A1 yes, C1 no -> 1/2; run 2: 0; run 3: 1
    assert (tags["reply"].episodes, tags["reply"].scenarios) == (4, 2)
    check(tags["reply"].success_rate, [0.5, 0.0, 1.0])
    # schedule: B and C; run 1: B1 yes, C1 no -> 1/2; run 2: 1; run 3: 1 -> mean 5/6, se 1/6
    assert (tags["schedule"].episodes, tags["schedule"].scenarios) == (4, 2)
    check(tags["schedule"].success_rate, [0.5, 1.0, 1.0])
    difficulty = metrics.breakdowns.difficulty
    assert list(difficulty) == ["easy", "hard"]
    check(difficulty["easy"].success_rate, [1.0, 0.0, 1.0])  # A
    check(difficulty["hard"].success_rate, [0.5, 1.0, 1.0])  # B and C


def test_breakdown_without_difficulty_is_unspecified() -> None:
    metrics = compute_metrics([record("D", 1, success=True)], label="x", runs=1, planned=[("D", 1)])
    assert list(metrics.breakdowns.difficulty) == ["unspecified"]
    assert metrics.breakdowns.tags == {}


def test_coverage(metrics: ConfigurationMetrics) -> None:
    coverage = metrics.coverage
    assert coverage.planned == 9
    assert coverage.complete == 7
    assert [(f.scenario_id, f.run, f.kind, f.message) for f in coverage.failed] == [
        ("C", 2, "provider_unavailable", "provider down")
    ]
    assert [(m.scenario_id, m.run) for m in coverage.missing] == [("C", 3)]
    assert coverage.unplanned == 2  # D1 and A4
    assert coverage.complete_share == pytest.approx(7 / 9)
    assert coverage.problems == 2


def test_format_errors_and_failed_steps(metrics: ConfigurationMetrics) -> None:
    # A1 observe 2, B2 observe 1 and user 1
    assert metrics.format_errors == {"observe": 3, "user": 1}
    assert metrics.failed_steps == {"execute": 1}


def test_bootstrap_is_deterministic_and_contains_the_estimate(metrics: ConfigurationMetrics) -> None:
    again = compute_metrics(fixture_records(), label="model-x", runs=3, planned=PLANNED)
    assert again.success_rate_ci == metrics.success_rate_ci
    assert metrics.success_rate_ci is not None
    low, high = metrics.success_rate_ci
    # scenario values: A 2/3, B 1, C 0 (its one complete run) -> mean 5/9
    assert low <= 5 / 9 <= high
    assert metrics.success_rate.mean is not None
    assert low <= metrics.success_rate.mean <= high
    # every resample mean is a multiple of 1/9 between 0 and 1
    assert 0.0 <= low < high <= 1.0
    assert metrics.confidence == 0.95
    assert metrics.bootstrap_samples == 2000


def test_bootstrap_seed_changes_the_draws_only() -> None:
    records = [record(s, 1, success=s in "AB") for s in "ABCDEF"]
    planned = [(s, 1) for s in "ABCDEF"]
    first = compute_metrics(records, label="x", runs=1, planned=planned, seed=1)
    second = compute_metrics(records, label="x", runs=1, planned=planned, seed=1)
    assert first.success_rate_ci == second.success_rate_ci
    assert first.success_rate_ci is not None
    low, high = first.success_rate_ci
    assert 0.0 <= low <= 2 / 6 <= high <= 1.0  # 2 of 6 scenarios succeeded
    others = {
        compute_metrics(
            records, label="x", runs=1, planned=planned, seed=s, bootstrap_samples=50
        ).success_rate_ci
        for s in range(5)
    }
    assert len(others) > 1


def test_bootstrap_degenerate_when_all_scenarios_agree() -> None:
    records = [record(s, r, success=True) for s in "AB" for r in (1, 2)]
    metrics = compute_metrics(records, label="x", runs=2, planned=[(s, r) for s in "AB" for r in (1, 2)])
    assert metrics.success_rate_ci == (1.0, 1.0)
    assert metrics.success_rate == Estimate(mean=1.0, se=0.0, n=2)


def test_nothing_complete() -> None:
    failed = record("A", 1, failure=Failure(kind="cache_miss", message="no entry"))
    metrics = compute_metrics([failed], label="x", runs=1, planned=[("A", 1), ("B", 1)])
    assert metrics.episodes_complete == 0
    assert metrics.success_rate == Estimate(mean=None, se=None, n=0)
    assert metrics.success_rate_ci is None
    assert metrics.proposals_per_episode is None
    assert metrics.usage["total"].tokens_per_episode is None
    assert metrics.usage["total"].cost_per_episode is None
    assert [(f.kind, f.message) for f in metrics.coverage.failed] == [("cache_miss", "no entry")]
    assert [m.scenario_id for m in metrics.coverage.missing] == ["B"]
    assert metrics.coverage.complete_share == 0.0


def test_invalid_input() -> None:
    with pytest.raises(ValueError, match=r"outside 1\.\.2"):
        compute_metrics([], label="x", runs=2, planned=[("A", 3)])
    with pytest.raises(ValueError, match="de-duplicate"):
        compute_metrics([record("A", 1), record("A", 1)], label="x", runs=1, planned=[("A", 1)])


def test_json_round_trip(metrics: ConfigurationMetrics) -> None:
    data = json.loads(json.dumps(metrics.model_dump(mode="json")))
    assert ConfigurationMetrics.model_validate(data) == metrics


def test_side_effects_are_counted_per_run_and_shown_in_the_main_table() -> None:
    records = [
        record("A", 1, side_effects=2),
        record("B", 1, success=True),
        record("A", 2, success=True),
        record("B", 2, success=True),
    ]
    metrics = compute_metrics(records, label="x", runs=2, planned=[(s, r) for s in "AB" for r in (1, 2)])
    assert metrics.side_effects == 1
    assert metrics.side_effect_rate.mean == 0.25 and metrics.side_effect_rate.n == 2
    header, row = render_csv([metrics]).splitlines()[:2]
    assert row.split(",")[header.split(",").index("side_effect_rate_mean")] == "0.25"
    assert "Side effects ± SE" in render_markdown([metrics], sections=["main"])


def harm_records() -> list[EpisodeRecord]:
    """k = 3, A and B: run 1 wrong 2 and 0 (irreversible calls 3 and 1), run 2 wrong 0 (2 calls) and an
    older record without the counts, run 3 only older records.
    """
    return [
        record("A", 1, side_effects=2, wrong_irreversible_actions=2, irreversible_actions=3),
        record("B", 1, success=True, wrong_irreversible_actions=0, irreversible_actions=1),
        record("A", 2, success=True, wrong_irreversible_actions=0, irreversible_actions=2),
        record("B", 2, success=True),
        record("A", 3, success=True),
        record("B", 3, success=True),
    ]


def harm_metrics() -> ConfigurationMetrics:
    planned = [(s, r) for s in "AB" for r in (1, 2, 3)]
    return compute_metrics(harm_records(), label="harm", runs=3, planned=planned)


def test_wrong_irreversible_actions_per_episode_leave_out_records_that_lack_them() -> None:
    metrics = harm_metrics()
    # run 1: (2 + 0) / 2 = 1.0; run 2: 0 / 1 (B2 has no count) = 0.0; run 3 has no count: skipped
    assert metrics.wrong_irreversible_actions == Estimate(mean=0.5, se=0.5, n=2)
    assert metrics.wrong_irreversible_total == 2
    # run 1: (3 + 1) / 2 = 2.0; run 2: 2 / 1 = 2.0
    assert metrics.irreversible_actions == Estimate(mean=2.0, se=0.0, n=2)


def test_records_written_before_harm_was_counted_still_read() -> None:
    old = record("A", 1).model_dump(mode="json")
    del old["irreversible_actions"], old["wrong_irreversible_actions"]
    read = EpisodeRecord.model_validate(old)
    assert read.irreversible_actions is None and read.wrong_irreversible_actions is None
    metrics = compute_metrics([read], label="old", runs=1, planned=[("A", 1)])
    assert metrics.wrong_irreversible_actions == Estimate() and metrics.wrong_irreversible_total == 0
