"""A batch of candidates: concurrent under the same limits as ``pare run``, with progress, resumable."""

from __future__ import annotations

import asyncio
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Protocol

from pare.agents.models import ModelCallCache, ModelClient, UsageLedger
from pare.errors import ProviderUnavailable, UserInputError, first_error
from pare.generate.config import GenerateConfig
from pare.generate.context import worked_example
from pare.generate.folder import CACHE, CandidateRecord, GenerationFolder, slot_name
from pare.generate.pipeline import Batch, Generators, generate_candidate
from pare.generate.prompts import system_prompt
from pare.output_paths import make_output_folder
from pare.scenarios.library import load_scenarios, scenario_files
from pare.scenarios.loader import load_scenario
from pare.scenarios.model import Scenario


class GenerationProgress(Protocol):
    """Told what the batch does, for a progress display."""

    def started(self, total: int, done: int) -> None:
        """The batch starts with ``done`` of ``total`` candidates finished in earlier sessions."""

    def stage(self, slot: str, stage: str, attempt: int) -> None:
        """A candidate entered a stage, or sends its answer number ``attempt``."""

    def finished(self, record: CandidateRecord) -> None:
        """A candidate finished (passed, duplicate or failed)."""

    def stopped(self) -> None:
        """The batch is over."""


class NoProgress:
    """Shows nothing."""

    def started(self, total: int, done: int) -> None:
        """Nothing."""

    def stage(self, slot: str, stage: str, attempt: int) -> None:
        """Nothing."""

    def finished(self, record: CandidateRecord) -> None:
        """Nothing."""

    def stopped(self) -> None:
        """Nothing."""


@dataclass
class GenerationSummary:
    """What one session of a batch did."""

    path: Path
    planned: int
    skipped: int
    records: list[CandidateRecord]
    unfinished: dict[str, str] = field(default_factory=dict)
    """Slots cut short by a provider that stayed down, with the reason: run again to resume them."""
    usage: dict[str, Any] = field(default_factory=dict)
    seconds: float = 0.0

    def count(self, status: str) -> int:
        """How many candidates of this session ended with ``status``."""
        return sum(record.status == status for record in self.records)


def _library(config: GenerateConfig) -> tuple[list[Scenario], dict[str, Path]]:
    paths = config.library or None
    scenarios = load_scenarios(paths)
    files = {path.stem: path for path in scenario_files(paths)}
    return scenarios, files


def _written(folder: GenerationFolder) -> list[Scenario]:
    """The candidates already in the folder (files that no longer load are left out of comparisons)."""
    found = []
    for path in sorted(folder.path.glob("*.yaml")):
        try:
            found.append(load_scenario(path))
        except UserInputError:
            continue
    return found


def generate(config: GenerateConfig, *, progress: GenerationProgress | None = None) -> GenerationSummary:
    """Run (or resume) the batch ``config`` describes: every slot without an outcome is generated."""
    progress = progress or NoProgress()
    started = time.perf_counter()
    for role, model in (("generator", config.generator), ("judge", config.judge_model)):
        ModelClient(model, role).api_key()  # a missing key fails before any folder is made
    make_output_folder(config.folder, "the candidates' folder")  # a path that cannot be one: said at once
    library, files = _library(config)
    folder = GenerationFolder.open(config)
    written = _written(folder)
    batch = Batch(
        config=config,
        folder=folder,
        library=library,
        system=system_prompt(worked_example(config.apps, library, files)),
        taken_ids={s.id for s in library} | folder.taken_ids(),
        written=written,
    )
    todo = [index for index in range(1, config.count + 1) if not folder.done(slot_name(index))]
    ledger = UsageLedger()
    cache = None if config.cache == "off" else ModelCallCache(str(folder.path / CACHE), mode=config.cache)
    summary = GenerationSummary(folder.path, config.count, config.count - len(todo), [])
    progress.started(config.count, config.count - len(todo))
    try:
        models = Generators(
            ModelClient(config.generator, "generator", cache=cache, ledger=ledger),
            ModelClient(config.judge_model, "judge", cache=cache, ledger=ledger),
        )
        asyncio.run(_run(todo, batch, models, progress, summary))
    finally:
        if cache is not None:
            cache.close()  # folds the write-ahead log into model_calls.sqlite
        progress.stopped()
        summary.usage = ledger.summary()
        summary.seconds = time.perf_counter() - started
    return summary


async def _run(
    todo: list[int],
    batch: Batch,
    models: Generators,
    progress: GenerationProgress,
    summary: GenerationSummary,
) -> None:
    queue = list(reversed(todo))

    async def worker() -> None:
        while queue:
            index = queue.pop()
            try:
                record = await generate_candidate(index, batch, models, progress)
            except ProviderUnavailable as error:
                summary.unfinished[slot_name(index)] = str(error)
                continue
            batch.folder.record(record)
            summary.records.append(record)
            progress.finished(record)

    try:
        async with asyncio.TaskGroup() as group:
            for _ in range(min(batch.config.concurrency, len(todo))):
                group.create_task(worker())
    except BaseExceptionGroup as errors:
        raise first_error(errors) from None
    finally:
        await models.aclose()
