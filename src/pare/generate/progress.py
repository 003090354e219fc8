"""The progress bar of ``pare generate``: candidates done of all, passed, duplicates, failed, cost so far,
and what the candidates in flight are doing (a batch's bar: :class:`pare.bench.progress.BatchProgress`).
"""

from __future__ import annotations

from rich.console import Console
from rich.progress import BarColumn, MofNCompleteColumn, TextColumn, TimeElapsedColumn

from pare.agents.models.ledger import RoleUsage
from pare.bench.progress import BatchProgress
from pare.generate.folder import CandidateRecord


class RichGenerationProgress(BatchProgress):
    """A rich progress bar fed by :func:`pare.generate.generate`."""

    unit = "candidates"
    resumed = "finished"

    def __init__(self, console: Console | None = None) -> None:
        super().__init__(
            (
                TextColumn("[bold]generating"),
                BarColumn(),
                MofNCompleteColumn(),
                TextColumn("{task.fields[tally]}"),
                TextColumn("cost {task.fields[cost]}"),
                TimeElapsedColumn(),
                TextColumn("{task.fields[doing]}"),
            ),
            console,
        )
        self.counts = {"passed": 0, "duplicate": 0, "failed": 0}
        self.doing: dict[str, str] = {}

    def started(self, total: int, done: int) -> None:
        """Show the bar; candidates finished in earlier sessions count as done."""
        self.begin("generate", total, done, **self._fields())

    def stage(self, slot: str, stage: str, attempt: int) -> None:
        """Say what a candidate in flight is doing."""
        self.doing[slot] = f"{slot[-3:]}:{stage}" + (f"#{attempt}" if attempt > 1 else "")
        self.update(**self._fields())

    def finished(self, record: CandidateRecord) -> None:
        """Advance by one candidate."""
        self.counts[record.status] += 1
        total = record.usage.get("total", {})
        self.count_usage(
            RoleUsage(
                calls=int(total.get("calls", 0)),
                known_cost_usd=float(total.get("known_cost_usd", 0.0)),
                unknown_cost_calls=int(total.get("unknown_cost_calls", 0)),
            )
        )
        self.doing.pop(record.slot, None)
        self.update(1, **self._fields())

    def stopped(self) -> None:
        """Leave the final state of the bar on screen."""
        self.doing.clear()
        self.update(**self._fields())
        self.stop()

    def _fields(self) -> dict[str, str]:
        counts = self.counts
        tally = f"{counts['passed']} passed, {counts['duplicate']} duplicate, {counts['failed']} failed"
        return {
            "tally": tally,
            "cost": self.cost(" + unpriced"),
            "doing": " ".join(sorted(self.doing.values()))[:60],
        }
