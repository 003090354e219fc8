"""The progress bar of ``pare run``: episodes done of all, successes so far, cost so far, time left, and
whether a model endpoint is being throttled (rate limited) now.
"""

from __future__ import annotations

from collections.abc import Sequence

from rich.console import Console
from rich.progress import (
    BarColumn,
    MofNCompleteColumn,
    Progress,
    TaskID,
    TextColumn,
    TimeElapsedColumn,
    TimeRemainingColumn,
)

from pare.agents.models.limiter import LimiterState
from pare.bench.throttling import throttling_status
from pare.results.records import EpisodeRecord
from pare.terminal_text import make_console, printable


class RichProgress:
    """A rich progress bar fed by the runner (see :class:`pare.bench.runner.ProgressSink`)."""

    def __init__(self, console: Console | None = None) -> None:
        self.console = console or make_console(stderr=True)
        self.progress = Progress(
            TextColumn("{task.description}", style="bold", markup=False),  # the run's label, as text
            BarColumn(),
            MofNCompleteColumn(),
            TextColumn("{task.fields[successes]} succeeded"),
            TextColumn("{task.fields[failed]}"),
            TextColumn("cost {task.fields[cost]}"),
            TimeElapsedColumn(),
            TextColumn("ETA"),
            TimeRemainingColumn(),
            TextColumn("[yellow]{task.fields[throttling]}"),
            console=self.console,
            transient=False,
        )
        self.task: TaskID | None = None
        self.successes = 0
        self.failed = 0
        self.known_cost = 0.0
        self.unpriced = False
        self.model_calls = 0
        self.throttled = ""

    def started(self, total: int, done: int, label: str) -> None:
        """Show the bar; episodes finished in earlier sessions count as done."""
        if done:
            self.console.print(f"resuming: {done} of {total} episodes are already recorded")
        self.progress.start()
        successes, failed, cost = self._fields()
        self.task = self.progress.add_task(
            printable(label),
            total=total,
            completed=done,
            successes=successes,
            failed=failed,
            cost=cost,
            throttling=self.throttled,
        )

    def finished(self, record: EpisodeRecord) -> None:
        """Advance by one episode."""
        self.successes += record.complete and record.success
        self.failed += not record.complete
        for usage in record.usage.values():
            self.known_cost += usage.known_cost_usd
            self.unpriced = self.unpriced or usage.unknown_cost_calls > 0
            self.model_calls += usage.calls
        if self.task is not None:
            successes, failed, cost = self._fields()
            self.progress.update(self.task, advance=1, successes=successes, failed=failed, cost=cost)

    def throttling(self, endpoints: Sequence[LimiterState]) -> None:
        """Show which endpoints are held back by rate limiting now (nothing when none is)."""
        status = throttling_status(endpoints)
        if status != self.throttled:
            self.throttled = status
            if self.task is not None:
                self.progress.update(self.task, throttling=status)

    def stopped(self) -> None:
        """Leave the final state of the bar on screen (without a throttling note that no longer holds)."""
        self.throttling(())
        self.progress.stop()

    def _fields(self) -> tuple[str, str, str]:
        """The bar's successes, failures and cost texts."""
        if not self.model_calls:  # no model was called (oracle runs): cost does not apply, it is not zero
            cost = "n/a"
        else:
            cost = f"${self.known_cost:.4f}" + (" + unpriced calls" if self.unpriced else "")
        failed = f"[red]{self.failed} failed (missing coverage)[/red]" if self.failed else ""
        return str(self.successes), failed, cost
