"""One candidate through the four stages: story (then the uniqueness check), seed, events, validation.

Each stage is one model call, or a short exchange: the answer is cut into its sections, the candidate is
loaded and played as far as it has got (:mod:`pare.generate.checking`), and the problems go back to the
model, at most ``stage_retries`` times, before the candidate is given up and reported.
"""

from __future__ import annotations

import asyncio
import time
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any, Protocol

from pare.agents.models import ChatMessage, ModelClient, UsageLedger
from pare.generate.checking import StageCheck, check_stage
from pare.generate.config import GenerateConfig
from pare.generate.folder import CandidateRecord, GenerationFolder, Status, slot_name
from pare.generate.prompts import feedback_prompt, stage_prompt
from pare.generate.sections import STAGE_KEYS, STAGES, assemble, extract_yaml, split_sections
from pare.generate.uniqueness import JudgeAnswerError, judge_story, measured_duplicate
from pare.scenarios.model import Scenario

REQUIRED: dict[str, tuple[str, ...]] = {
    "story": (),  # the loader names the story's missing fields itself
    "seed": ("seed",),
    "events": ("oracle",),
    "validation": ("goals", "variants"),
}
"""Sections a stage must have written before its candidate is played."""
MAX_PROBLEMS = 25
"""The most problems sent back in one feedback message (the rest follow once these are fixed)."""


class StageListener(Protocol):
    """Told when a candidate enters a stage or sends an answer back (progress display)."""

    def stage(self, slot: str, stage: str, attempt: int) -> None:
        """Candidate ``slot`` is at ``stage``, answer number ``attempt``."""


@dataclass
class Batch:
    """What every candidate of a batch shares: the settings, the folder, the library to compare with,
    the system prompt, and the ids and stories taken so far (growing as candidates pass).
    """

    config: GenerateConfig
    folder: GenerationFolder
    library: list[Scenario]
    system: str
    taken_ids: set[str] = field(default_factory=set)
    written: list[Scenario] = field(default_factory=list)
    """Candidates in the folder, from earlier sessions and this one: compared with like the library."""

    def comparison(self) -> list[Scenario]:
        """The scenarios a new story must differ from."""
        return [*self.library, *self.written]

    def taken_titles(self) -> list[str]:
        """The titles a story prompt lists as taken: the comparison set's scenarios using a chosen app."""
        wanted = set(self.config.apps)
        return sorted(s.title for s in self.comparison() if wanted & set(s.apps))


@dataclass
class Generators:
    """The generator's and the judge's model clients."""

    generator: ModelClient
    judge: ModelClient

    async def aclose(self) -> None:
        """Close both clients' connections."""
        await self.generator.aclose()
        await self.judge.aclose()


class StageFailed(Exception):
    """A stage ran out of answers with problems left."""

    def __init__(self, stage: str, problems: Sequence[str], messages: list[dict[str, Any]], attempts: int):
        super().__init__(f"{stage}: {len(problems)} problem(s) after {attempts} answer(s)")
        self.stage = stage
        self.problems = list(problems)
        self.messages = messages
        self.attempts = attempts


@dataclass
class _Candidate:
    """One slot's work in progress."""

    index: int
    slot: str
    ledger: UsageLedger = field(default_factory=UsageLedger)
    sections: dict[str, str] = field(default_factory=dict)
    attempts: dict[str, int] = field(default_factory=dict)
    hashes: dict[str, str] = field(default_factory=dict)
    turns: str = ""
    """What the runs played at the last finished stage took (the validation stage is told)."""
    started: float = field(default_factory=time.perf_counter)


async def generate_candidate(
    index: int, batch: Batch, models: Generators, listener: StageListener | None = None
) -> CandidateRecord:
    """Run candidate slot ``index`` through the four stages; the record says how it ended.

    :class:`~pare.errors.ProviderUnavailable` and configuration mistakes propagate (the slot stays
    unfinished, to be resumed).
    """
    work = _Candidate(index, slot_name(index))
    check: StageCheck | None = None
    try:
        for stage in STAGES:
            check, messages = await _stage(stage, work, batch, models, listener)
            work.hashes[stage] = batch.folder.write_transcript(
                work.slot, stage, messages, attempts=work.attempts[stage]
            )
            if stage == "story" and check.scenario is not None:
                duplicate = await _story_duplicate(check.scenario, work, batch, models)
                if duplicate is not None:
                    return duplicate
    except StageFailed as failure:
        work.attempts[failure.stage] = failure.attempts
        work.hashes[failure.stage] = batch.folder.write_transcript(
            work.slot, failure.stage, failure.messages, attempts=failure.attempts, problems=failure.problems
        )
        return _record(
            work,
            "failed",
            stage=failure.stage,
            reason=f"the {failure.stage} stage still had {len(failure.problems)} problem(s) after "
            f"{failure.attempts} answer(s)",
            problems=failure.problems,
        )
    assert check is not None and check.scenario is not None
    scenario = check.scenario
    measured = measured_duplicate(scenario, batch.comparison())
    if measured is not None:
        return _record(work, "duplicate", stage="validation", reason=measured.reason, scenario_id=scenario.id)
    file = batch.folder.write_candidate(scenario.id, assemble(work.sections), _provenance(work, batch))
    batch.written.append(scenario)
    return _record(work, "passed", scenario_id=scenario.id, file=file)


async def _stage(
    stage: str, work: _Candidate, batch: Batch, models: Generators, listener: StageListener | None
) -> tuple[StageCheck, list[dict[str, Any]]]:
    """One stage's exchange: answers until the gate finds nothing, or :class:`StageFailed`."""
    config = batch.config
    tag, difficulty = config.focus(work.index)
    prompt = stage_prompt(
        stage,
        apps=config.apps,
        candidate=assemble(work.sections),
        index=work.index,
        count=config.count,
        tag=tag,
        tags=config.tags,
        difficulty=difficulty,
        difficulties=config.difficulty,
        taken=batch.taken_titles(),
        turns=work.turns,
    )
    messages = [ChatMessage.system(batch.system), ChatMessage.user(prompt)]
    position = STAGES.index(stage)
    allowed = [*STAGE_KEYS[stage], *(key for earlier in STAGES[1:position] for key in STAGE_KEYS[earlier])]
    problems: Sequence[str] = ()
    for attempt in range(1, config.stage_retries + 2):
        if listener is not None:
            listener.stage(work.slot, stage, attempt)
        answer = await models.generator.complete(messages, namespace=work.slot, ledger=work.ledger)
        messages.append(answer.message())
        work.attempts[stage] = attempt
        split = split_sections(extract_yaml(answer.text), allowed)
        trial = {**work.sections, **split.sections}
        missing = [key for key in REQUIRED[stage] if key not in trial]
        played, turns = False, ""
        if answer.cut_from is not None:  # a runaway answer: cut to the cap, never taken as sections
            problems = [
                f"your answer was {answer.cut_from:,} characters long, more than the generator may write, "
                "and was cut: write only the sections asked for"
            ]
        elif split.problems or missing:
            problems = [*split.problems, *(f"the '{key}' section is missing: write it" for key in missing)]
        else:
            check = await asyncio.to_thread(
                check_stage, stage, trial, config, taken_ids=frozenset(batch.taken_ids)
            )
            problems, played, turns = check.problems, check.played, check.turns
            if not problems and stage == "story" and check.scenario is not None:
                if check.scenario.id in batch.taken_ids:  # taken by a candidate in flight meanwhile
                    problems = [f"id: '{check.scenario.id}' is taken by another scenario; choose another"]
                else:
                    batch.taken_ids.add(check.scenario.id)
            if not problems:
                work.sections = trial
                work.turns = check.turns
                return check, [message.to_openai() for message in messages]
        if attempt <= config.stage_retries:
            left = config.stage_retries - attempt + 1
            shown = list(problems[:MAX_PROBLEMS])
            if len(problems) > MAX_PROBLEMS:
                shown.append(f"... and {len(problems) - MAX_PROBLEMS} more")
            messages.append(
                ChatMessage.user(feedback_prompt(stage, shown, played=played, left=left, turns=turns))
            )
    raise StageFailed(
        stage, problems, [message.to_openai() for message in messages], config.stage_retries + 1
    )


async def _story_duplicate(
    scenario: Scenario, work: _Candidate, batch: Batch, models: Generators
) -> CandidateRecord | None:
    """The uniqueness check after the story: the record of a duplicate (or of an unreadable verdict)."""
    config = batch.config
    try:
        verdict = await judge_story(
            scenario,
            batch.comparison(),
            models.judge,
            floor=config.prefilter,
            top=config.neighbours,
            namespace=work.slot,
            ledger=work.ledger,
        )
    except JudgeAnswerError as error:
        return _record(work, "failed", stage="story", reason=f"the uniqueness judge's answer: {error}")
    if verdict.messages:
        work.hashes["judge"] = batch.folder.write_transcript(
            work.slot, "judge", verdict.messages, duplicate=verdict.duplicate, reason=verdict.reason
        )
        work.attempts["judge"] = sum(m.get("role") == "assistant" for m in verdict.messages)
    if not verdict.duplicate:
        return None
    same = f" (same as '{verdict.same_as}')" if verdict.same_as else ""
    return _record(
        work,
        "duplicate",
        stage="story",
        reason=f"the judge found it retells a library story{same}: {verdict.reason}",
        scenario_id=scenario.id,
    )


def _provenance(work: _Candidate, batch: Batch) -> dict[str, Any]:
    config = batch.config
    tag, difficulty = config.focus(work.index)
    return {
        "slot": work.slot,
        "generator": config.generator.public_dict(),
        "judge": config.judge_model.public_dict(),
        "settings": {
            "apps": config.apps,
            "tags": config.tags,
            "difficulty": config.difficulty,
            "focus": {"tag": tag, "difficulty": difficulty},
            "stage_retries": config.stage_retries,
            "prefilter": config.prefilter,
        },
        "attempts": work.attempts,
        "transcripts": work.hashes,
    }


def _record(
    work: _Candidate,
    status: Status,
    *,
    stage: str | None = None,
    reason: str = "",
    problems: Sequence[str] = (),
    scenario_id: str | None = None,
    file: str | None = None,
) -> CandidateRecord:
    return CandidateRecord(
        slot=work.slot,
        index=work.index,
        status=status,
        scenario_id=scenario_id,
        file=file,
        stage=stage,
        reason=reason,
        problems=list(problems),
        attempts=dict(work.attempts),
        transcripts=dict(work.hashes),
        usage=work.ledger.summary(),
        seconds=time.perf_counter() - work.started,
    )
