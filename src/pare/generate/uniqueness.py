"""Is a candidate's story new? ``pare scenarios similar``'s measure as a cheap first filter against the
library, then a model judge against the nearest library stories; and the whole measure once the
candidate is complete.
"""

from __future__ import annotations

import json
import re
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

from pare.agents.models import ChatMessage, ModelClient, UsageLedger
from pare.generate.prompts import judge_prompt
from pare.scenarios.model import Scenario
from pare.scenarios.similarity import (
    THRESHOLD,
    WEIGHTS,
    cosine,
    jaccard,
    similarities,
    text_words,
    word_vectors,
)

JUDGE_RETRIES = 1
"""Times an unreadable verdict goes back to the judge."""


@dataclass(frozen=True, slots=True)
class Neighbour:
    """A library scenario near a candidate's story."""

    scenario_id: str
    title: str
    story: str
    score: float


@dataclass(frozen=True, slots=True)
class Uniqueness:
    """Whether a candidate retells a library story, and why; ``messages`` is the judge's conversation
    (empty when the filter decided alone).
    """

    duplicate: bool
    reason: str
    same_as: str | None = None
    messages: list[dict[str, Any]] = field(default_factory=list)


class JudgeAnswerError(Exception):
    """The judge's answer could not be read as a verdict."""


def nearest_stories(candidate: Scenario, library: Sequence[Scenario], top: int) -> list[Neighbour]:
    """The ``top`` library scenarios nearest to ``candidate`` by story and apps (the measure of ``pare
    scenarios similar`` without the oracle's tools, which a story does not have yet), nearest first.
    """
    others = [scenario for scenario in library if scenario.id != candidate.id]
    if not others:
        return []
    vectors = word_vectors(
        [text_words(s.title, s.story) for s in others] + [text_words(candidate.title, candidate.story)]
    )
    mine, apps = vectors[-1], set(candidate.all_apps)
    weight = WEIGHTS["story"] + WEIGHTS["apps"]
    scored = [
        Neighbour(
            other.id,
            other.title,
            " ".join(other.story.split()),
            (WEIGHTS["story"] * cosine(mine, vector) + WEIGHTS["apps"] * jaccard(apps, set(other.all_apps)))
            / weight,
        )
        for other, vector in zip(others, vectors, strict=False)
    ]
    return sorted(scored, key=lambda n: (-n.score, n.scenario_id))[:top]


async def judge_story(
    candidate: Scenario,
    library: Sequence[Scenario],
    client: ModelClient,
    *,
    floor: float,
    top: int,
    namespace: str,
    ledger: UsageLedger | None = None,
) -> Uniqueness:
    """Filter by the measure, then ask the judge about the nearest stories when the nearest reaches
    ``floor``.
    """
    neighbours = nearest_stories(candidate, library, top)
    if not neighbours or neighbours[0].score < floor:
        nearest = f"'{neighbours[0].scenario_id}' at {neighbours[0].score:.2f}" if neighbours else "none"
        return Uniqueness(
            False, f"no library story near it (nearest {nearest}, judge asked from {floor:.2f})"
        )
    messages = [ChatMessage.user(judge_prompt(candidate, neighbours))]
    for attempt in range(JUDGE_RETRIES + 1):
        answer = await client.complete(messages, namespace=namespace, ledger=ledger)
        messages.append(answer.message())
        try:
            duplicate, same_as, reason = read_verdict(answer.text)
        except JudgeAnswerError as error:
            if attempt == JUDGE_RETRIES:
                raise
            messages.append(ChatMessage.user(f"{error} Answer with the JSON object only."))
            continue
        transcript = [message.to_openai() for message in messages]
        return Uniqueness(duplicate, reason, same_as, transcript)
    raise AssertionError("unreachable")  # pragma: no cover


def read_verdict(text: str) -> tuple[bool, str | None, str]:
    """``(duplicate, same_as, reason)`` from the judge's JSON answer."""
    found = re.search(r"\{.*\}", text, re.S)
    if found is None:
        raise JudgeAnswerError("The answer holds no JSON object.")
    try:
        data = json.loads(found.group(0))
    except (ValueError, RecursionError) as error:  # invalid JSON, an integer of too many digits, too deep
        raise JudgeAnswerError(f"The JSON object cannot be read ({error}).") from None
    if not isinstance(data, dict) or not isinstance(data.get("duplicate"), bool):
        raise JudgeAnswerError('The object needs "duplicate": true or false.')
    same_as = data.get("same_as")
    reason = data.get("reason")
    return (
        data["duplicate"],
        same_as if isinstance(same_as, str) and same_as else None,
        reason.strip() if isinstance(reason, str) and reason.strip() else "(no reason given)",
    )


def measured_duplicate(candidate: Scenario, library: Sequence[Scenario]) -> Uniqueness | None:
    """The complete candidate against the library by ``pare scenarios similar``'s whole measure: a
    duplicate when a pair reaches its threshold.
    """
    others = [scenario for scenario in library if scenario.id != candidate.id]
    for pair in similarities([*others, candidate]):
        if pair.score < THRESHOLD:
            return None
        if candidate.id in (pair.first, pair.second):
            other = pair.second if pair.first == candidate.id else pair.first
            return Uniqueness(
                True,
                f"pare scenarios similar scores it {pair.score:.2f} against '{other}' "
                f"(threshold {THRESHOLD})",
                other,
            )
    return None
