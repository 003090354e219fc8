"""The leaderboard: one row per configuration, ranked by success, with the numbers people compare
configurations by (success with its interval, pass^k, acceptance, side effects, cost per success) and who
played the user. Shown when the viewer has two configurations or more; sorted in the page by
``leaderboard.js``, each cell carrying its number for sorting beside the text it shows.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

from pare.results import report
from pare.results.exports.episodes import role_players
from pare.viewer._runs import Configuration

NOTHING = "\N{EN DASH}"


@dataclass(frozen=True)
class Cell:
    """What a cell shows and the number it sorts by (``None``: not measured, sorted last)."""

    text: str
    value: float | None


@dataclass(frozen=True)
class LeaderboardRow:
    """One configuration on the leaderboard."""

    rank: int
    configuration: Configuration
    assistant: str
    user: str
    episodes: Cell
    success: Cell
    interval: Cell
    pass_hat: Cell
    acceptance: Cell
    side_effects: Cell
    cost_per_success: Cell


def leaderboard(configurations: Sequence[Configuration]) -> list[LeaderboardRow]:
    """The configurations ranked by success rate (unmeasured last), then by label."""

    def order(configuration: Configuration) -> tuple[float, str]:
        mean = configuration.metrics.success_rate.mean
        return (-(mean if mean is not None else -1.0), configuration.label)

    return [_row(rank, c) for rank, c in enumerate(sorted(configurations, key=order), start=1)]


def _row(rank: int, configuration: Configuration) -> LeaderboardRow:
    m = configuration.metrics
    players = role_players(configuration.loaded.manifest)
    low, high = m.success_rate_ci if m.success_rate_ci is not None else (None, None)
    k = m.runs
    pass_k = m.pass_hat.get(k)
    total = m.usage.get("total")
    cost = total.cost_per_success if total is not None else None
    return LeaderboardRow(
        rank=rank,
        configuration=configuration,
        assistant=players["assistant"],
        user=players["user"],
        episodes=Cell(f"{m.episodes_complete}/{m.episodes_planned}", m.episodes_complete),
        success=Cell(report.format_estimate(m.success_rate, missing=NOTHING), m.success_rate.mean),
        interval=Cell(
            NOTHING if low is None or high is None else f"{low:.0%} to {high:.0%}",
            low,
        ),
        pass_hat=Cell(f"pass^{k} {report.format_percent(pass_k, missing=NOTHING)}", pass_k),
        acceptance=Cell(report.format_estimate(m.acceptance_rate, missing=NOTHING), m.acceptance_rate.mean),
        side_effects=Cell(
            report.format_estimate(m.side_effect_rate, missing=NOTHING), m.side_effect_rate.mean
        ),
        cost_per_success=Cell(NOTHING if cost is None else f"${cost:.4f}", cost),
    )
