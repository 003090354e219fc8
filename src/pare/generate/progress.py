"""The progress bar of ``pare generate``: candidates done of all, passed, duplicates, failed, cost so far,
and what the candidates in flight are doing.
"""

from __future__ import annotations

from rich.console import Console
from rich.progress import BarColumn, MofNCompleteColumn, Progress, TaskID, TextColumn, TimeElapsedColumn

from pare.generate.folder import CandidateRecord
from pare.terminal_text import make_console


class RichGenerationProgress:
    """A rich progress bar fed by :func:`pare.generate.generate`."""

    def __init__(self, console: Console | None = None) -> None:
        self.console = console or make_console(stderr=True)
        self.progress = Progress(
            TextColumn("[bold]generating"),
            BarColumn(),
            MofNCompleteColumn(),
            TextColumn("{task.fields[tally]}"),
            TextColumn("cost {task.fields[cost]}"),
            TimeElapsedColumn(),
            TextColumn("{task.fields[doing]}"),
            console=self.console,
        )
        self.task: TaskID | None = None
        self.counts = {"passed": 0, "duplicate": 0, "failed": 0}
        self.cost = 0.0
        self.unpriced = False
        self.calls = 0
        self.doing: dict[str, str] = {}

    def started(self, total: int, done: int) -> None:
        """Show the bar; candidates finished in earlier sessions count as done."""
        if done:
            self.console.print(f"resuming: {done} of {total} candidates are already finished")
        self.progress.start()
        tally, cost, doing = self._fields()
        self.task = self.progress.add_task(
            "generate", total=total, completed=done, tally=tally, cost=cost, doing=doing
        )

    def stage(self, slot: str, stage: str, attempt: int) -> None:
        """Say what a candidate in flight is doing."""
        self.doing[slot] = f"{slot[-3:]}:{stage}" + (f"#{attempt}" if attempt > 1 else "")
        self._update(advance=0)

    def finished(self, record: CandidateRecord) -> None:
        """Advance by one candidate."""
        self.counts[record.status] += 1
        total = record.usage.get("total", {})
        self.calls += int(total.get("calls", 0))
        self.cost += float(total.get("known_cost_usd", 0.0))
        self.unpriced = self.unpriced or bool(total.get("unknown_cost_calls"))
        self.doing.pop(record.slot, None)
        self._update(advance=1)

    def stopped(self) -> None:
        """Leave the final state of the bar on screen."""
        self.doing.clear()
        self._update(advance=0)
        self.progress.stop()

    def _update(self, advance: int) -> None:
        if self.task is not None:
            tally, cost, doing = self._fields()
            self.progress.update(self.task, advance=advance, tally=tally, cost=cost, doing=doing)

    def _fields(self) -> tuple[str, str, str]:
        counts = self.counts
        tally = f"{counts['passed']} passed, {counts['duplicate']} duplicate, {counts['failed']} failed"
        cost = "n/a" if not self.calls else f"${self.cost:.4f}" + (" + unpriced" if self.unpriced else "")
        return tally, cost, " ".join(sorted(self.doing.values()))[:60]
