"""Render :class:`~pare.results.metrics.ConfigurationMetrics` as terminal tables, Markdown, CSV or JSON.

The terminal and Markdown renderers draw the same tables, built once from the metrics: the paper's
main table (Table 1), the decision analysis, the gather-context resolution, cost and tokens per role,
breakdowns per app, tag and difficulty, and the coverage problems. Percentages read like the paper's
("42.0% ± 1.0%": mean ± standard error across runs); a number that cannot be computed reads "n/a" and
a cost that is not known reads "unknown", never "$0".
"""

from __future__ import annotations

import csv
import io
import json
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, field
from typing import Any

from rich.cells import cell_len
from rich.console import Console
from rich.padding import Padding
from rich.table import Table

from pare.errors import UserInputError, did_you_mean
from pare.results.metrics import TOTAL, ConfigurationMetrics, Estimate, GroupMetrics, UsageSummary
from pare.results.records import DECISIONS, FAULT_KINDS, RESOLUTIONS
from pare.results.report_sections import SECTIONS as SECTIONS  # re-exported: reports are asked by section
from pare.terminal_text import plain_text, printable

__all__ = [
    "SECTIONS",
    "format_ci",
    "format_estimate",
    "format_percent",
    "format_usd",
    "render_csv",
    "render_json",
    "render_markdown",
    "render_terminal",
]

NA = "n/a"
UNKNOWN = "unknown"

_DECISION_NAMES = {
    "accept": "Accept",
    "reject": "Reject",
    "gather_context": "Gather context",
    "truncated": "Truncated",
}
_RESOLUTION_NAMES = {
    "accepted": "G→Accept",
    "rejected": "G→Reject",
    "expired": "G→Expired",
    "truncated": "G→Truncated",
}


def format_percent(value: float | None, *, missing: str = NA) -> str:
    """``0.42`` as ``"42.0%"``; ``None`` as ``missing`` (``"n/a"``)."""
    return missing if value is None else f"{value * 100:.1f}%"


def format_estimate(estimate: Estimate, *, percent: bool = True, digits: int = 1, missing: str = NA) -> str:
    """An estimate as ``"42.0% ± 1.0%"`` (or ``"20.2 ± 0.2"`` with ``percent=False``).

    The ``± SE`` part is left out when the standard error is undefined (fewer than two runs), and the
    whole reads ``missing`` (``"n/a"``) when there was nothing to measure.
    """
    if estimate.mean is None:
        return missing
    if percent:
        text = format_percent(estimate.mean)
        return text if estimate.se is None else f"{text} ± {format_percent(estimate.se)}"
    text = f"{estimate.mean:.{digits}f}"
    return text if estimate.se is None else f"{text} ± {estimate.se:.{digits}f}"


def format_ci(interval: tuple[float, float] | None) -> str:
    """A confidence interval as ``"[35.0%, 49.0%]"``; ``None`` as ``"n/a"``."""
    return NA if interval is None else f"[{format_percent(interval[0])}, {format_percent(interval[1])}]"


def format_usd(value: float | None, *, known: bool = True) -> str:
    """Dollars as ``"$0.0123"``; ``"unknown"`` when the cost is not known, else ``"n/a"`` for ``None``."""
    if not known:
        return UNKNOWN
    return NA if value is None else f"${value:.4f}"


def _format_count(value: float | None) -> str:
    """A token count per episode as ``"1,100"``."""
    return NA if value is None else f"{value:,.0f}"


@dataclass(frozen=True)
class _Report:
    """One table of a report, independent of how it is drawn."""

    section: str
    title: str
    columns: tuple[str, ...]
    text_columns: int = 1
    """How many leading columns hold names (aligned left); the rest hold numbers (aligned right)."""
    rows: list[tuple[str, ...]] = field(default_factory=list)
    row_styles: list[str | None] = field(default_factory=list)
    style: str | None = None
    note: str | None = None

    def add(self, *cells: str, style: str | None = None) -> None:
        """Append a row."""
        self.rows.append(cells)
        self.row_styles.append(style)


def _check_sections(sections: Iterable[str]) -> tuple[str, ...]:
    """The chosen sections, checked against :data:`SECTIONS`."""
    chosen = tuple(sections)
    for name in chosen:
        if name not in SECTIONS:
            raise UserInputError(
                f"unknown report section {name!r}.{did_you_mean(name, SECTIONS)} "
                f"Choose from: {', '.join(SECTIONS)}."
            )
    return chosen


def _same(metrics: Sequence[ConfigurationMetrics], value: Callable[[ConfigurationMetrics], Any]) -> Any:
    """``value`` of the configurations when they all agree on it, else ``None``."""
    values = {value(m) for m in metrics}
    return values.pop() if len(values) == 1 else None


def protocol_text(m: ConfigurationMetrics) -> str:
    """The protocol a configuration played: its preset, and its overrides (``paper (max_turns=20)``)."""
    if not m.protocol_overrides:
        return m.protocol
    overrides = ", ".join(
        f"{name}={'none' if value is None else value}" for name, value in m.protocol_overrides.items()
    )
    return f"{m.protocol} ({overrides})"


def protocol_heading(metrics: Sequence[ConfigurationMetrics]) -> str:
    """Every report's first line: the protocol the configurations played (each its own when they differ)."""
    texts = {protocol_text(m) for m in metrics}
    if len(texts) == 1:
        return f"Protocol: {texts.pop()}"
    return "Protocols: " + "; ".join(f"{m.label}: {protocol_text(m)}" for m in metrics)


def _main_table(metrics: Sequence[ConfigurationMetrics]) -> _Report:
    k = _same(metrics, lambda m: m.runs)
    confidence = _same(metrics, lambda m: m.confidence)
    level = f"{confidence * 100:g}% CI" if confidence is not None else "CI"
    suffix = "k" if k is None else str(k)
    table = _Report(
        "main",
        "Main results",
        (
            "Configuration",
            f"Success@{suffix}",
            f"Success^{suffix}",
            "Success rate ± SE",
            level,
            "Wrong irreversible / episode ± SE",
            "User did it ± SE",
            "Side effects ± SE",
            "Proposal rate ± SE",
            "Per observe turn ± SE",
            "Acceptance rate ± SE",
            "Read actions ± SE",
            "Coverage",
        ),
        note="± is the standard error across runs; Success@k and Success^k count only scenarios whose k "
        "runs are all complete. Wrong irreversible: the assistant's calls per episode that cannot be "
        "undone (a sent message, a deletion) and made a change no solution of the scenario makes. User "
        "did it: failed episodes in which the user made by hand what a goal "
        "wanted from the assistant (failures of the assistant, already in the success rate). Side "
        "effects: episodes in which the assistant changed something no solution of the scenario changes "
        "(failures, already in the success rate). Proposal rate: proposals per turn, the paper's definition; "
        "per observe turn: per turn in which the assistant was watching rather than executing.",
    )
    for m in metrics:
        covered = f"{m.coverage.complete}/{m.coverage.planned}"
        share = m.coverage.complete_share
        table.add(
            m.label,
            format_percent(m.success_at_k),
            format_percent(m.success_all_k),
            format_estimate(m.success_rate),
            format_ci(m.success_rate_ci),
            format_estimate(m.wrong_irreversible_actions, percent=False, digits=2),
            format_estimate(m.user_did_work_rate),
            format_estimate(m.side_effect_rate),
            format_estimate(m.proposal_rate),
            format_estimate(m.observe_proposal_rate),
            format_estimate(m.acceptance_rate),
            format_estimate(m.read_actions, percent=False),
            covered if share is None or share == 1 else f"{covered} ({format_percent(share)})",
        )
    return table


def _decisions_table(metrics: Sequence[ConfigurationMetrics]) -> _Report:
    table = _Report(
        "decisions",
        "Proposal decisions",
        ("Configuration", *(_DECISION_NAMES[d] for d in DECISIONS), "Proposals"),
        note="The user's first step after each proposal: share of proposals per run, ± SE across runs.",
    )
    for m in metrics:
        table.add(m.label, *(format_estimate(m.decisions[d]) for d in DECISIONS), str(m.proposals))
    return table


def _resolution_table(metrics: Sequence[ConfigurationMetrics]) -> _Report:
    table = _Report(
        "resolution",
        "Gather-context resolution",
        ("Configuration", *(_RESOLUTION_NAMES[r] for r in RESOLUTIONS), "Gather-context proposals"),
        note="How the proposals the user did not answer at once finally ended, ± SE across runs.",
    )
    for m in metrics:
        cells = (format_estimate(m.gather_context_resolution[r]) for r in RESOLUTIONS)
        table.add(m.label, *cells, str(m.gather_context_proposals))
    return table


def _reliability_table(metrics: Sequence[ConfigurationMetrics]) -> _Report:
    table = _Report(
        "reliability",
        "Success over k runs",
        ("Configuration", "k", "pass^k", "pass@k"),
        text_columns=2,
        note="pass^k: the chance that k runs of a scenario all succeed; pass@k: that at least one does. "
        "Unbiased estimates from each scenario's complete runs (C(c,k)/C(n,k) and 1 - C(n-c,k)/C(n,k)), "
        "averaged over scenarios with at least k complete runs; at k = n they are Success^k and Success@k.",
    )
    for m in metrics:
        for k in sorted(m.pass_hat):
            table.add(m.label, str(k), format_percent(m.pass_hat[k]), format_percent(m.pass_at.get(k)))
    return table


def _consistency_table(metrics: Sequence[ConfigurationMetrics]) -> _Report:
    table = _Report(
        "consistency",
        "Consistency and reward",
        ("Configuration", "Scenarios that flip", "Flip rate", "R_Accept / episode ± SE"),
        note="A scenario flips when its complete runs disagree on the verdict (counted over scenarios with "
        "two complete runs or more). R_Accept is the paper's per-step reward: +1 per accepted proposal, "
        "-1 per rejected one, summed over the episode.",
    )
    for m in metrics:
        table.add(
            m.label,
            str(m.flip_scenarios),
            format_percent(m.flip_rate),
            format_estimate(m.accept_reward, percent=False, digits=2),
        )
    return table


def _simulator_table(metrics: Sequence[ConfigurationMetrics]) -> _Report:
    table = _Report(
        "simulator",
        "User simulator faults",
        (
            "Configuration",
            "Failures with a fault",
            "Success rate without faults ± SE",
            "Episodes without a fault",
            *(kind.replace("_", " ").capitalize() for kind in FAULT_KINDS),
        ),
        note="What the simulated user did wrong on its own (accepted a proposal against its goal, rejected "
        "the solution's, did the task by hand after accepting, stalled, typed facts it was never shown): "
        "the share of failed episodes with such a fault, and the success rate over the episodes without "
        "one; then the episodes with each kind.",
    )
    for m in metrics:
        faults = m.simulator
        share = format_percent(faults.failure_fault_share)
        table.add(
            m.label,
            f"{share} ({faults.failures_with_fault}/{faults.failures})",
            format_estimate(faults.success_rate_without_faults),
            str(faults.episodes_without_fault),
            *(str(faults.kinds.get(kind, 0)) for kind in FAULT_KINDS),
        )
    return table


def _cost_table(metrics: Sequence[ConfigurationMetrics]) -> _Report:
    table = _Report(
        "cost",
        "Cost and tokens per role",
        (
            "Configuration",
            "Role",
            "Calls",
            "Tokens / episode",
            "Prompt / episode",
            "Completion / episode",
            "Cost",
            "Cost / episode",
            "Cost / success",
        ),
        text_columns=2,
        note="Over complete episodes; 'unknown' when a model's price is not known; "
        "n/a where no model was called.",
    )
    for m in metrics:
        for role, usage in m.usage.items():
            table.add(m.label, role, *_usage_cells(usage), style="bold" if role == TOTAL else None)
    return table


def _usage_cells(usage: UsageSummary) -> tuple[str, ...]:
    known = usage.cost_usd is not None
    if not usage.calls:  # no model played this role (the oracle): cost and tokens do not apply
        return ("0", NA, NA, NA, NA, NA, NA)
    return (
        str(usage.calls),
        _format_count(usage.tokens_per_episode),
        _format_count(usage.prompt_tokens_per_episode),
        _format_count(usage.completion_tokens_per_episode),
        usage.cost,
        format_usd(usage.cost_per_episode, known=known),
        format_usd(usage.cost_per_success, known=known),
    )


def _breakdown_table(
    metrics: Sequence[ConfigurationMetrics],
    section: str,
    title: str,
    heading: str,
    groups: Callable[[ConfigurationMetrics], dict[str, GroupMetrics]],
) -> _Report:
    table = _Report(
        section,
        title,
        (
            heading,
            "Configuration",
            "Scenarios",
            "Episodes",
            "Success rate ± SE",
            "Proposal rate ± SE",
            "Acceptance rate ± SE",
        ),
        text_columns=2,
        note="Complete episodes whose scenario lists the value; a scenario counts toward each of its values.",
    )
    values = sorted({value for m in metrics for value in groups(m)})
    for value in values:
        for m in metrics:
            group = groups(m).get(value)
            if group is None:
                continue
            table.add(
                value,
                m.label,
                str(group.scenarios),
                str(group.episodes),
                format_estimate(group.success_rate),
                format_estimate(group.proposal_rate),
                format_estimate(group.acceptance_rate),
            )
    return table


def _coverage_table(metrics: Sequence[ConfigurationMetrics]) -> _Report:
    table = _Report(
        "coverage",
        "Coverage problems",
        ("Configuration", "Scenario", "Run", "Problem", "Reason"),
        text_columns=5,
        style="yellow",
        note="Failed and missing episodes are left out of every metric: rerun them to complete coverage.",
    )
    for m in metrics:
        for failed in m.coverage.failed:
            table.add(
                m.label,
                failed.scenario_id,
                str(failed.run),
                f"failed ({failed.kind})",
                failed.message,
                style="red",
            )
        for missing in m.coverage.missing:
            table.add(m.label, missing.scenario_id, str(missing.run), "missing", "no record", style="yellow")
    return table


def _tables(metrics: Sequence[ConfigurationMetrics], sections: Iterable[str]) -> list[_Report]:
    """The chosen tables, in :data:`SECTIONS` order; the coverage table only when it has rows."""
    chosen = set(_check_sections(sections))
    builders: dict[str, Callable[[], _Report]] = {
        "main": lambda: _main_table(metrics),
        "decisions": lambda: _decisions_table(metrics),
        "resolution": lambda: _resolution_table(metrics),
        "reliability": lambda: _reliability_table(metrics),
        "consistency": lambda: _consistency_table(metrics),
        "simulator": lambda: _simulator_table(metrics),
        "cost": lambda: _cost_table(metrics),
        "kinds": lambda: _breakdown_table(metrics, "kinds", "By kind", "Kind", lambda m: m.breakdowns.kinds),
        "apps": lambda: _breakdown_table(metrics, "apps", "By app", "App", lambda m: m.breakdowns.apps),
        "tags": lambda: _breakdown_table(metrics, "tags", "By tag", "Tag", lambda m: m.breakdowns.tags),
        "difficulty": lambda: _breakdown_table(
            metrics, "difficulty", "By difficulty", "Difficulty", lambda m: m.breakdowns.difficulty
        ),
        "coverage": lambda: _coverage_table(metrics),
    }
    tables = [builders[name]() for name in SECTIONS if name in chosen]
    return [table for table in tables if table.rows or table.section != "coverage"]


def render_terminal(
    metrics: Sequence[ConfigurationMetrics], console: Console, *, sections: Iterable[str] = SECTIONS
) -> None:
    """Print the chosen sections as rich tables; coverage problems only when there are any. Every cell
    is text, never markup: labels, ids and failure messages come from run folders and providers.

    A table whose cells do not fit the console on one line each (most CI logs are 80 columns) would have
    its headers cut ("Succ…") and its values split: it is printed as one block per row instead, each
    value beside its full column name.

    Raises:
        UserInputError: On an unknown section name.
    """
    tables = _tables(metrics, sections)
    if not metrics:
        console.print("No results to report.")
        return
    console.print(plain_text(protocol_heading(metrics), "bold"))
    for report in tables:
        console.print()
        widths = _cell_widths(report)
        if sum(widths) + _BORDERS_PER_COLUMN * len(widths) + 1 > console.width:
            _print_blocks(report, console)
        else:
            console.print(_rich_table(report, _fitted_widths(report, widths, console.width)))


_BORDERS_PER_COLUMN = 3
"""What a rich table adds to each column: a rule and a space either side."""


def _cell_widths(report: _Report) -> list[int]:
    """Each column's width: its widest cell, or its header's longest word. The table is drawn only when
    every cell fits on one line (headers may wrap at their spaces): narrower, rich would cut headers to
    "Succ…" and split values.
    """
    widths = [max(cell_len(word) for word in printable(column).split() or [""]) for column in report.columns]
    for row in report.rows:
        for position, cell in enumerate(row):
            widths[position] = max(widths[position], cell_len(printable(cell)))
    return widths


def _fitted_widths(report: _Report, widths: Sequence[int], room: int) -> list[int]:
    """Each column's width for a table ``room`` wide, given the least each needs (``widths``): the
    least, plus a fair share of what is left toward its widest cell or unwrapped header.

    Rich narrows the widest columns first when a table does not fit, below what their cells need, then
    measures them again at that need: the table came out wider than the console and was cut at its
    right edge. Widths worked out here, each at least the column's need, are what rich draws.
    """
    wanted = [cell_len(printable(column)) for column in report.columns]
    for row in report.rows:
        for position, cell in enumerate(row):
            wanted[position] = max(wanted[position], cell_len(printable(cell)))
    fitted = list(widths)
    spare = room - sum(fitted) - _BORDERS_PER_COLUMN * len(fitted) - 1
    hungry = sorted(range(len(fitted)), key=lambda position: wanted[position] - fitted[position])
    for left, position in enumerate(hungry):
        share = max(spare, 0) // (len(hungry) - left)  # what the columns not yet served may each have
        grant = min(max(wanted[position] - fitted[position], 0), share)
        fitted[position] += grant
        spare -= grant
    return fitted


def _rich_table(report: _Report, widths: Sequence[int]) -> Table:
    table = Table(
        title=plain_text(report.title),
        title_justify="left",
        title_style=_title_style(report),
        caption=plain_text(report.note),
        caption_justify="left",
    )
    for position, column in enumerate(report.columns):
        table.add_column(
            plain_text(column),
            justify="left" if position < report.text_columns else "right",
            width=widths[position],
        )
    for row, style in zip(report.rows, report.row_styles, strict=True):
        table.add_row(*(plain_text(cell) for cell in row), style=style)
    return table


def _title_style(report: _Report) -> str:
    return f"bold {report.style}" if report.style else "bold"


def _print_blocks(report: _Report, console: Console) -> None:
    """``report`` for a narrow console: its title, then per row a heading (the row's names) and one line
    per other column, ``column  value``; the note last.
    """
    console.print(plain_text(report.title, _title_style(report)))
    names = report.columns[report.text_columns :]
    for row, style in zip(report.rows, report.row_styles, strict=True):
        heading = " · ".join(cell for cell in row[: report.text_columns] if cell)
        console.print(plain_text(heading, f"bold {style}" if style else "bold"))
        lines = Table.grid(padding=(0, 2))
        lines.add_column(style="dim")
        lines.add_column(justify="left")
        for name, cell in zip(names, row[report.text_columns :], strict=True):
            lines.add_row(plain_text(name), plain_text(cell))
        console.print(Padding(lines, (0, 0, 0, 2)))
    if report.note:
        console.print(plain_text(report.note, "dim"))


def render_markdown(metrics: Sequence[ConfigurationMetrics], *, sections: Iterable[str] = SECTIONS) -> str:
    """The chosen sections as GitHub Markdown: a ``##`` heading and a pipe table each.

    Raises:
        UserInputError: On an unknown section name.
    """
    tables = _tables(metrics, sections)
    if not metrics:
        return "No results to report.\n"
    parts: list[str] = [protocol_heading(metrics) + "\n"]
    for report in tables:
        lines = [f"## {report.title}", ""]
        if report.note:
            lines += [report.note, ""]
        lines.append(_markdown_row(report.columns))
        align = (":---" if i < report.text_columns else "---:" for i in range(len(report.columns)))
        lines.append("|" + "|".join(align) + "|")
        lines += [_markdown_row(row) for row in report.rows]
        parts.append("\n".join(lines) + "\n")
    return "\n".join(parts)


def _markdown_row(cells: Iterable[str]) -> str:
    # a pipe inside a cell would end it; newlines would end the row
    escaped = (cell.replace("|", "\\|").replace("\n", " ") for cell in cells)
    return "| " + " | ".join(escaped) + " |"


LATEX_SPECIALS = {
    "\\": r"\textbackslash{}",
    "&": r"\&",
    "%": r"\%",
    "$": r"\$",
    "#": r"\#",
    "_": r"\_",
    "{": r"\{",
    "}": r"\}",
    "~": r"\textasciitilde{}",
    "^": r"\textasciicircum{}",
    "±": r"$\pm$",
    "→": r"$\rightarrow$",
}


def _latex(text: str) -> str:
    """``text`` with LaTeX's special characters escaped (``±`` and ``→`` as math symbols)."""
    return "".join(LATEX_SPECIALS.get(char, char) for char in text)


def render_latex(metrics: Sequence[ConfigurationMetrics], *, sections: Iterable[str] = SECTIONS) -> str:
    """The chosen sections as LaTeX ``table`` environments with booktabs rules, like the paper's tables
    (``booktabs`` package); each table's note becomes its caption.

    Raises:
        UserInputError: On an unknown section name.
    """
    tables = _tables(metrics, sections)
    if not metrics:
        return "% No results to report.\n"
    parts: list[str] = []
    heading = _latex(protocol_heading(metrics))
    for report in tables:
        note = " " + _latex(report.note) if report.note else ""
        align = "".join("l" if i < report.text_columns else "r" for i in range(len(report.columns)))
        lines = [
            "\\begin{table}[ht]",
            "\\centering",
            f"\\begin{{tabular}}{{{align}}}",
            "\\toprule",
            " & ".join(rf"\textbf{{{_latex(column)}}}" for column in report.columns) + r" \\",
            "\\midrule",
            *(" & ".join(_latex(cell) for cell in row) + r" \\" for row in report.rows),
            "\\bottomrule",
            "\\end{tabular}",
            f"\\caption{{{_latex(report.title)}. {heading}.{note}}}",
            f"\\label{{tab:pare-{report.section}}}",
            "\\end{table}",
        ]
        parts.append("\n".join(lines) + "\n")
    return "\n".join(parts)


def render_csv(metrics: Sequence[ConfigurationMetrics]) -> str:
    """One row per configuration with flat columns.

    Columns: ``label``; ``protocol`` (the preset and its overrides); ``param.<name>`` for every parameter
    any configuration has (strings as they are, other values as JSON); counts and coverage;
    ``<metric>_mean``, ``<metric>_se`` and ``<metric>_n`` for every estimate; the success-rate interval;
    ``decision.<name>_*`` and ``resolution.<name>_*``; ``pass_hat.<k>`` and ``pass_at.<k>`` for every k up
    to the most runs any configuration has; ``usage.<role>.*`` for every role and the total. Empty cells
    are values that could not be computed (or a cost that is not known; ``usage.<role>.cost`` says which).
    """
    rows = [_csv_row(m) for m in metrics]
    params = sorted({name for m in metrics for name in m.params})
    roles = [*sorted({role for m in metrics for role in m.usage if role != TOTAL}), TOTAL]
    columns = ["label", "protocol", *(f"param.{name}" for name in params)]
    columns += list(_CSV_COLUMNS)
    ks = sorted({k for m in metrics for k in m.pass_hat})
    columns += [f"pass_hat.{k}" for k in ks] + [f"pass_at.{k}" for k in ks]
    for role in roles:
        columns += [f"usage.{role}.{name}" for name in _USAGE_COLUMNS]
    buffer = io.StringIO()
    writer = csv.DictWriter(buffer, fieldnames=columns, lineterminator="\n", restval="")
    writer.writeheader()
    for m, row in zip(metrics, rows, strict=True):
        row["label"] = m.label
        row["protocol"] = protocol_text(m)
        for name in params:
            if name in m.params:
                value = m.params[name]
                row[f"param.{name}"] = value if isinstance(value, str) else json.dumps(value, sort_keys=True)
        writer.writerow(row)
    return buffer.getvalue()


_ESTIMATES = (
    "success_rate",
    "goal_rate",
    "user_did_work_rate",
    "side_effect_rate",
    "wrong_irreversible_actions",
    "irreversible_actions",
    "proposal_rate",
    "observe_proposal_rate",
    "accept_reward",
    "acceptance_rate",
    "read_actions",
    "turns",
)
_USAGE_COLUMNS = (
    "calls",
    "prompt_tokens",
    "completion_tokens",
    "total_tokens",
    "tokens_per_episode",
    "cost_usd",
    "known_cost_usd",
    "unknown_cost_calls",
    "cost_per_episode",
    "cost_per_success",
    "cost",
)
_CSV_COLUMNS: tuple[str, ...] = (
    "runs",
    "scenarios",
    "episodes_planned",
    "episodes_complete",
    "episodes_failed",
    "episodes_missing",
    "episodes_unplanned",
    "complete_share",
    "scenarios_fully_covered",
    "successes",
    "success_at_k",
    "success_all_k",
    *(f"{name}_{part}" for name in _ESTIMATES for part in ("mean", "se", "n")),
    "success_rate_ci_low",
    "success_rate_ci_high",
    "confidence",
    "wrong_irreversible_total",
    "proposals",
    "accepted",
    "proposals_per_episode",
    *(f"decision.{name}_{part}" for name in DECISIONS for part in ("mean", "se", "n")),
    "gather_context_proposals",
    "flip_scenarios",
    "flip_rate",
    *(f"resolution.{name}_{part}" for name in RESOLUTIONS for part in ("mean", "se", "n")),
    "simulator.failures",
    "simulator.failures_with_fault",
    "simulator.failure_fault_share",
    *(f"simulator.success_rate_without_faults_{part}" for part in ("mean", "se", "n")),
    "simulator.episodes_without_fault",
    *(f"simulator.fault.{kind}" for kind in FAULT_KINDS),
)


def _cell(value: object) -> str:
    """A CSV cell: empty for ``None``, ``repr``-exact for floats."""
    return "" if value is None else str(value)


def _estimate_cells(prefix: str, estimate: Estimate) -> dict[str, str]:
    return {
        f"{prefix}_mean": _cell(estimate.mean),
        f"{prefix}_se": _cell(estimate.se),
        f"{prefix}_n": _cell(estimate.n),
    }


def _csv_row(m: ConfigurationMetrics) -> dict[str, str]:
    ci = m.success_rate_ci
    row = {
        "runs": _cell(m.runs),
        "scenarios": _cell(m.scenarios),
        "episodes_planned": _cell(m.episodes_planned),
        "episodes_complete": _cell(m.episodes_complete),
        "episodes_failed": _cell(len(m.coverage.failed)),
        "episodes_missing": _cell(len(m.coverage.missing)),
        "episodes_unplanned": _cell(m.coverage.unplanned),
        "complete_share": _cell(m.coverage.complete_share),
        "scenarios_fully_covered": _cell(m.scenarios_fully_covered),
        "successes": _cell(m.successes),
        "success_at_k": _cell(m.success_at_k),
        "success_all_k": _cell(m.success_all_k),
        "success_rate_ci_low": _cell(None if ci is None else ci[0]),
        "success_rate_ci_high": _cell(None if ci is None else ci[1]),
        "confidence": _cell(m.confidence),
        "wrong_irreversible_total": _cell(m.wrong_irreversible_total),
        "proposals": _cell(m.proposals),
        "accepted": _cell(m.accepted),
        "proposals_per_episode": _cell(m.proposals_per_episode),
        "gather_context_proposals": _cell(m.gather_context_proposals),
        "flip_scenarios": _cell(m.flip_scenarios),
        "flip_rate": _cell(m.flip_rate),
    }
    row.update({f"pass_hat.{k}": _cell(value) for k, value in m.pass_hat.items()})
    row.update({f"pass_at.{k}": _cell(value) for k, value in m.pass_at.items()})
    for name in _ESTIMATES:
        row.update(_estimate_cells(name, getattr(m, name)))
    for decision in DECISIONS:
        row.update(_estimate_cells(f"decision.{decision}", m.decisions[decision]))
    for resolution in RESOLUTIONS:
        row.update(_estimate_cells(f"resolution.{resolution}", m.gather_context_resolution[resolution]))
    row.update(_simulator_cells(m))
    for role, usage in m.usage.items():
        data = usage.model_dump()
        row.update({f"usage.{role}.{name}": _cell(data[name]) for name in _USAGE_COLUMNS})
    return row


def _simulator_cells(m: ConfigurationMetrics) -> dict[str, str]:
    faults = m.simulator
    row = {
        "simulator.failures": _cell(faults.failures),
        "simulator.failures_with_fault": _cell(faults.failures_with_fault),
        "simulator.failure_fault_share": _cell(faults.failure_fault_share),
        "simulator.episodes_without_fault": _cell(faults.episodes_without_fault),
        **{f"simulator.fault.{kind}": _cell(faults.kinds.get(kind, 0)) for kind in FAULT_KINDS},
    }
    row.update(_estimate_cells("simulator.success_rate_without_faults", faults.success_rate_without_faults))
    return row


def render_json(metrics: Sequence[ConfigurationMetrics]) -> str:
    """``{"configurations": [...]}``, each configuration's ``model_dump(mode="json")``, in the order given.

    Keys are sorted and the indentation fixed (2), so equal metrics give byte-identical text.
    """
    data = {"configurations": [m.model_dump(mode="json") for m in metrics]}
    return json.dumps(data, indent=2, sort_keys=True, ensure_ascii=False) + "\n"
