"""The simulator-fault figures of a configuration, worked out by hand; old records read without faults."""

from __future__ import annotations

from pare.results.metrics import compute_metrics
from pare.results.records import EpisodeRecord, SimulatorFault
from tests.results.test_metrics import record

STALL = SimulatorFault(kind="stalled", turn=3, detail="left it to expire", proposal_id="p1")
TYPED = SimulatorFault(kind="unseen_fact", turn=2, detail="typed 555-0142")


def test_share_of_failures_with_a_fault_and_success_without_them() -> None:
    # run 1: A ok, B failed with a stall, C failed; run 2: A ok, B failed with a stall and a typed fact, C ok
    records = [
        record("A", 1, success=True),
        record("B", 1, simulator_faults=[STALL]),
        record("C", 1),
        record("A", 2, success=True),
        record("B", 2, simulator_faults=[STALL, TYPED]),
        record("C", 2, success=True),
    ]
    planned = [(s, r) for s in "ABC" for r in (1, 2)]
    faults = compute_metrics(records, label="m", runs=2, planned=planned).simulator
    assert (faults.failures, faults.failures_with_fault) == (3, 2)
    assert faults.failure_fault_share == 2 / 3
    assert faults.episodes_with_fault == 2 and faults.episodes_without_fault == 4
    # without B: run 1 = 1/2, run 2 = 2/2 -> mean 0.75, SE = stdev(0.5, 1) / sqrt(2) = 0.25
    assert faults.success_rate_without_faults.mean == 0.75
    assert faults.success_rate_without_faults.se == 0.25
    assert faults.kinds == {
        "accepted_wrong": 0,
        "rejected_right": 0,
        "did_by_hand": 0,
        "stalled": 2,
        "unseen_fact": 1,
    }


def test_a_record_written_before_faults_were_recorded_reads_with_none() -> None:
    line = record("A", 1).model_dump(mode="json")
    del line["simulator_faults"]
    read = EpisodeRecord.model_validate(line)
    assert read.simulator_faults == [] and not read.simulator_fault
