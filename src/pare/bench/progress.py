"""Progress bars of batches: ``pare run``'s episodes and ``pare generate``'s candidates.

:class:`BatchProgress` is what every batch shows: units done of all (units finished in an earlier session
count as done), the cost of model calls so far ("n/a" while no model was called, never "$0"), the time
elapsed. :class:`RichProgress` adds a run's successes, failures, time left and rate limiting; the
generator's bar (:mod:`pare.generate.progress`) adds its tally and what the candidates in flight do.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

from rich.console import Console
from rich.progress import (
    BarColumn,
    MofNCompleteColumn,
    Progress,
    ProgressColumn,
    TaskID,
    TextColumn,
    TimeElapsedColumn,
    TimeRemainingColumn,
)

from pare.agents.models.ledger import RoleUsage
from pare.agents.models.limiter import LimiterState
from pare.bench.throttling import throttling_status
from pare.results.records import EpisodeRecord
from pare.terminal_text import make_console, printable


class BatchProgress:
    """A rich progress bar over a batch of ``unit`` (its columns given by the subclass)."""

    unit = "items"
    """What the batch is made of, plural: "episodes", "candidates"."""
    resumed = "finished"
    """What units of an earlier session are: "recorded", "finished"."""

    def __init__(self, columns: Sequence[ProgressColumn], console: Console | None = None) -> None:
        self.console = console or make_console(stderr=True)
        self.progress = Progress(*columns, console=self.console, transient=False)
        self.task: TaskID | None = None
        self.known_cost = 0.0
        self.unpriced = False
        self.model_calls = 0

    def begin(self, description: str, total: int, done: int, **fields: Any) -> None:
        """Show the bar (units of earlier sessions count as done, and are said to)."""
        if done:
            self.console.print(f"resuming: {done} of {total} {self.unit} are already {self.resumed}")
        self.progress.start()
        self.task = self.progress.add_task(printable(description), total=total, completed=done, **fields)

    def count_usage(self, usage: RoleUsage) -> None:
        """Add one unit's model usage to the cost so far."""
        self.known_cost += usage.known_cost_usd
        self.unpriced = self.unpriced or usage.unknown_cost_calls > 0
        self.model_calls += usage.calls

    def cost(self, unpriced: str = " + unpriced calls") -> str:
        """The cost so far: "n/a" while no model was called (it does not apply, it is not zero)."""
        if not self.model_calls:
            return "n/a"
        return f"${self.known_cost:.4f}" + (unpriced if self.unpriced else "")

    def update(self, advance: int = 0, /, **fields: Any) -> None:
        """Advance the bar and change its fields."""
        if self.task is not None:
            self.progress.update(self.task, advance=advance, **fields)

    def stop(self) -> None:
        """Leave the final state of the bar on screen."""
        self.progress.stop()


class RichProgress(BatchProgress):
    """``pare run``'s bar, fed by the runner (see :class:`pare.bench.runner.ProgressSink`): episodes done
    of all, successes, failures, cost, time elapsed and left, and whether an endpoint is rate limited.
    """

    unit = "episodes"
    resumed = "recorded"

    def __init__(self, console: Console | None = None) -> None:
        super().__init__(
            (
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
            ),
            console,
        )
        self.successes = 0
        self.failed = 0
        self.throttled = ""

    def started(self, total: int, done: int, label: str) -> None:
        """Show the bar; episodes finished in earlier sessions count as done."""
        self.begin(label, total, done, **self._fields(), throttling=self.throttled)

    def finished(self, record: EpisodeRecord) -> None:
        """Advance by one episode."""
        self.successes += record.complete and record.success
        self.failed += not record.complete
        for usage in record.usage.values():
            self.count_usage(usage)
        self.update(1, **self._fields())

    def throttling(self, endpoints: Sequence[LimiterState]) -> None:
        """Show which endpoints are held back by rate limiting now (nothing when none is)."""
        status = throttling_status(endpoints)
        if status != self.throttled:
            self.throttled = status
            self.update(throttling=status)

    def stopped(self) -> None:
        """Leave the final state of the bar on screen (without a throttling note that no longer holds)."""
        self.throttling(())
        self.stop()

    def _fields(self) -> dict[str, str]:
        """The bar's successes, failures and cost texts."""
        failed = f"[red]{self.failed} failed (missing coverage)[/red]" if self.failed else ""
        return {"successes": str(self.successes), "failed": failed, "cost": self.cost()}
