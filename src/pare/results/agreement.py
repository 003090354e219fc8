"""How often people agree with the user simulator and with the judge: Cohen's kappa from a run's annotations.

Each person's last verdict on an item (:mod:`pare.results.annotations`) is paired with the machine's:

* a proposal with the user simulator's answer, read from the episode's record: resolved ``accepted`` is
  accept, ``rejected`` is reject; a proposal the simulator never answered (expired, or pending at the end)
  has no answer to agree with and is counted apart (``unanswered``);
* a judged text with the judge's verdict, read from the episode's trajectory.

Per configuration and rater (``user`` or ``judge``) the report gives the pairs, the observed agreement and
Cohen's kappa, ``(p_o - p_e) / (1 - p_e)`` with ``p_e`` the agreement expected by chance from the two
sides' positive rates. Its interval is a percentile bootstrap over *items* (an item's pairs, one per person
who marked it, are resampled together, so several people marking one proposal do not pass for independent
evidence); resamples in which kappa is undefined (both sides gave one label only) are left out, and the
interval is ``None`` when fewer than half of them remain. Kappa is ``None`` when ``p_e`` is 1.
"""

from __future__ import annotations

import random
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Literal

from pydantic import BaseModel, ConfigDict, Field

from pare.results.annotations import Annotation, judged_items, latest_annotations, read_annotations
from pare.results.records import EpisodeRecord
from pare.results.run_folder import LoadedRun
from pare.results.trajectory import Trajectory, read_trajectory

Rater = Literal["user", "judge"]
RATERS: tuple[Rater, ...] = ("user", "judge")
RATER_OF_KIND: Mapping[str, Rater] = {"proposal": "user", "judged": "judge"}
Pair = tuple[bool, bool]
"""(the person's verdict, the machine's), True for accept or pass."""


class Agreement(BaseModel):
    """People against one rater of one configuration."""

    model_config = ConfigDict(extra="forbid", frozen=True)

    label: str = Field(description="The configuration.")
    rater: Rater = Field(description="user: the user simulator's answers; judge: the judge's verdicts.")
    items: int = Field(description="Items with at least one pair.")
    annotators: int = Field(description="People who gave a pair.")
    pairs: int
    both_positive: int = Field(description="Pairs where both accepted (passed).")
    person_only: int = Field(description="Pairs where only the person accepted (passed).")
    machine_only: int = Field(description="Pairs where only the machine accepted (passed).")
    both_negative: int
    unanswered: int = Field(default=0, description="Marked proposals the simulator never answered.")
    observed: float | None = Field(description="Share of pairs that agree.")
    kappa: float | None
    kappa_ci: tuple[float, float] | None
    confidence: float
    bootstrap_samples: int


def cohen_kappa(pairs: Sequence[Pair]) -> float | None:
    """Cohen's kappa of two raters' yes/no verdicts; ``None`` without pairs or when chance agreement is 1."""
    if not pairs:
        return None
    n = len(pairs)
    observed = sum(left == right for left, right in pairs) / n
    left_yes = sum(left for left, _ in pairs) / n
    right_yes = sum(right for _, right in pairs) / n
    expected = left_yes * right_yes + (1 - left_yes) * (1 - right_yes)
    if expected >= 1:
        return None
    return (observed - expected) / (1 - expected)


def kappa_interval(
    items: Sequence[Sequence[Pair]], *, samples: int, confidence: float, rng: random.Random
) -> tuple[float, float] | None:
    """Percentile bootstrap interval of kappa, resampling ``items`` (an item's pairs go together)."""
    if not items:
        return None
    values: list[float] = []
    for _ in range(samples):
        drawn = [pair for _ in items for pair in items[rng.randrange(len(items))]]
        value = cohen_kappa(drawn)
        if value is not None:
            values.append(value)
    if len(values) * 2 < samples:
        return None
    values.sort()
    tail = (1 - confidence) / 2
    return (_quantile(values, tail), _quantile(values, 1 - tail))


def _quantile(ordered: Sequence[float], q: float) -> float:
    position = q * (len(ordered) - 1)
    low = int(position)
    high = min(low + 1, len(ordered) - 1)
    return ordered[low] + (ordered[high] - ordered[low]) * (position - low)


def agreement_of_run(
    loaded: LoadedRun,
    annotations: Sequence[Annotation] | None = None,
    *,
    samples: int = 2000,
    confidence: float = 0.95,
    seed: int = 0,
) -> list[Agreement]:
    """People's agreement with the user simulator and with the judge in one run (its folder's annotations
    unless ``annotations`` are given); a rater nobody marked an item of is left out.
    """
    marks = latest_annotations(read_annotations(loaded.path) if annotations is None else annotations)
    records = {record.key: record for record in loaded.records if record.complete}
    machine: dict[tuple[str, int], dict[str, bool | None]] = {}
    by_item: dict[Rater, dict[tuple[str, int, str], list[Pair]]] = {rater: {} for rater in RATERS}
    people: dict[Rater, set[str]] = {rater: set() for rater in RATERS}
    unanswered = 0
    for mark in marks:
        record = records.get((mark.scenario_id, mark.run))
        if record is None:
            continue  # an episode no longer in the run (or not complete): nothing to compare with
        if mark_key(mark) not in machine:
            machine[mark_key(mark)] = _machine_verdicts(loaded.path, record)
        name = f"{mark.kind}/{mark.item}"
        if name not in machine[mark_key(mark)]:
            continue  # no such item in the episode
        verdict = machine[mark_key(mark)][name]
        if verdict is None:  # a proposal the simulator never answered
            unanswered += 1
            continue
        rater = RATER_OF_KIND[mark.kind]
        by_item[rater].setdefault((mark.scenario_id, mark.run, mark.item), []).append(
            (mark.positive, verdict)
        )
        people[rater].add(mark.annotator)
    found = []
    for rater in RATERS:
        items = list(by_item[rater].values())
        if not items and not (rater == "user" and unanswered):
            continue
        pairs = [pair for item in items for pair in item]
        found.append(
            Agreement(
                label=loaded.label,
                rater=rater,
                items=len(items),
                annotators=len(people[rater]),
                pairs=len(pairs),
                both_positive=sum(person and other for person, other in pairs),
                person_only=sum(person and not other for person, other in pairs),
                machine_only=sum(other and not person for person, other in pairs),
                both_negative=sum(not person and not other for person, other in pairs),
                unanswered=unanswered if rater == "user" else 0,
                observed=sum(person == other for person, other in pairs) / len(pairs) if pairs else None,
                kappa=cohen_kappa(pairs),
                kappa_ci=kappa_interval(
                    items, samples=samples, confidence=confidence, rng=random.Random(seed)
                ),
                confidence=confidence,
                bootstrap_samples=samples,
            )
        )
    return found


def mark_key(mark: Annotation) -> tuple[str, int]:
    """The episode an annotation is about."""
    return (mark.scenario_id, mark.run)


def _machine_verdicts(folder: Path, record: EpisodeRecord) -> dict[str, bool | None]:
    """The simulator's answer to each proposal (``None``: never answered) and the judge's verdict on each
    judged text of an episode, by ``kind/item``.
    """
    answers = {"accepted": True, "rejected": False}
    verdicts: dict[str, bool | None] = {
        f"proposal/{p.proposal_id}": answers.get(p.resolution) for p in record.proposals
    }
    for judged in judged_items(episode_trajectory(folder, record)):
        verdicts[f"judged/{judged.item}"] = judged.passed
    return verdicts


def episode_trajectory(folder: Path, record: EpisodeRecord) -> Trajectory | None:
    """An episode's trajectory (``None`` when the record names none).

    Raises:
        UserInputError: The file is missing, damaged or of a newer format (named).
    """
    if record.trajectory is None:
        return None
    return read_trajectory(folder / record.trajectory)
