"""A calibration's measures as tables: for the terminal, Markdown, LaTeX, CSV or JSON.

Every format is made from the same tables (:func:`calibration_tables`): a title, column headers and rows
of text, one set per calibrated user, so the formats never disagree.
"""

from __future__ import annotations

import csv
import io
import json
from collections.abc import Sequence
from dataclasses import dataclass

from rich.console import Console
from rich.table import Table

from pare.results.calibration import CalibrationMetrics, GroupRow, Rate, wilson


@dataclass(frozen=True)
class TextTable:
    """One table of a report: its title, headers and rows of text."""

    title: str
    headers: tuple[str, ...]
    rows: tuple[tuple[str, ...], ...]


def rate_text(rate: Rate) -> str:
    """``12.5% [4.1, 32.0] (2/16)``, or ``-`` when there is nothing to count."""
    if rate.value is None or rate.low is None or rate.high is None:
        return "-"
    return f"{100 * rate.value:.1f}% [{100 * rate.low:.1f}, {100 * rate.high:.1f}] ({rate.hits}/{rate.total})"


def heading(metrics: CalibrationMetrics) -> str:
    """Who was calibrated, under which protocol and persona of trust."""
    return f"{metrics.label}: protocol {metrics.protocol}, user trust {metrics.user_trust}"


def calibration_tables(metrics: CalibrationMetrics) -> list[TextTable]:
    """The report's tables for one calibrated user."""
    confusion = TextTable(
        "Decisions (rows: the right answer)",
        ("right answer", "accepted", "rejected", "no answer"),
        tuple(
            (expected, *(str(metrics.confusion[expected][d]) for d in ("accept", "reject", "no_answer")))
            for expected in ("accept", "reject")
        ),
    )
    rates = TextTable(
        "Error rates (Wilson 95% interval)",
        ("measure", "rate"),
        (
            ("accept when wrong", rate_text(metrics.accept_when_wrong)),
            ("reject when right", rate_text(metrics.reject_when_right)),
            ("no answer", rate_text(metrics.no_answer)),
        ),
    )
    after = metrics.after_looking
    gathering = TextTable(
        "Looking things up before answering",
        ("measure", "value"),
        (
            ("cases looked into first", rate_text(metrics.looked)),
            ("actions per case", "-" if metrics.mean_looked is None else f"{metrics.mean_looked:.2f}"),
            (
                "then accepted / rejected / no answer",
                f"{after['accept']} / {after['reject']} / {after['no_answer']}",
            ),
        ),
    )
    coverage = TextTable(
        "Coverage",
        ("planned", "complete", "failed", "not reached", "cost"),
        (
            (
                str(metrics.planned),
                str(metrics.complete),
                str(metrics.failed),
                str(metrics.not_reached),
                f"${metrics.cost_usd:.4f}",
            ),
        ),
    )
    return [
        confusion,
        rates,
        gathering,
        _groups("By case kind", "kind", metrics.by_kind),
        _groups("By app", "app", metrics.by_app),
        _groups("By tag", "tag", metrics.by_tag),
        coverage,
    ]


def _groups(title: str, name: str, rows: Sequence[GroupRow]) -> TextTable:
    return TextTable(
        title,
        (name, "cases", "decided rightly", "accept when wrong", "reject when right"),
        tuple(
            (
                row.group,
                str(row.cases),
                rate_text(row.right),
                rate_text(row.accept_when_wrong),
                rate_text(row.reject_when_right),
            )
            for row in rows
        ),
    )


def render_terminal(metrics: Sequence[CalibrationMetrics], console: Console) -> None:
    """Print each calibrated user's tables with rich."""
    for item in metrics:
        console.print(f"[bold]{_escape(heading(item))}[/bold]")
        for table in calibration_tables(item):
            shown = Table(title=table.title, title_justify="left")
            for header in table.headers:
                shown.add_column(header)
            for row in table.rows:
                shown.add_row(*(_escape(cell) for cell in row))
            console.print(shown)


def _escape(text: str) -> str:
    from rich.markup import escape

    return escape(text)


def render_markdown(metrics: Sequence[CalibrationMetrics]) -> str:
    """Each calibrated user's tables as Markdown."""
    parts: list[str] = []
    for item in metrics:
        parts.append(f"## {heading(item)}\n")
        for table in calibration_tables(item):
            parts.append(f"**{table.title}**\n")
            parts.append("| " + " | ".join(table.headers) + " |")
            parts.append("|" + "---|" * len(table.headers))
            parts.extend(
                "| " + " | ".join(cell.replace("|", "\\|") for cell in row) + " |" for row in table.rows
            )
            parts.append("")
    return "\n".join(parts)


_LATEX_SPECIAL = {"&": r"\&", "%": r"\%", "$": r"\$", "#": r"\#", "_": r"\_", "{": r"\{", "}": r"\}"}


def _latex(text: str) -> str:
    return "".join(_LATEX_SPECIAL.get(char, char) for char in text)


def render_latex(metrics: Sequence[CalibrationMetrics]) -> str:
    """Each calibrated user's tables as LaTeX tabulars (booktabs rules)."""
    parts: list[str] = []
    for item in metrics:
        parts.append(f"% {_latex(heading(item))}")
        for table in calibration_tables(item):
            parts.append(f"% {_latex(table.title)}")
            parts.append(r"\begin{tabular}{l" + "r" * (len(table.headers) - 1) + "}")
            parts.append(r"\toprule")
            parts.append(" & ".join(_latex(h) for h in table.headers) + r" \\")
            parts.append(r"\midrule")
            parts.extend(" & ".join(_latex(cell) for cell in row) + r" \\" for row in table.rows)
            parts.append(r"\bottomrule")
            parts.append(r"\end{tabular}")
            parts.append("")
    return "\n".join(parts)


def render_csv(metrics: Sequence[CalibrationMetrics]) -> str:
    """One row per user and group (``all``, each case kind, app and tag): counts and rates as numbers."""
    out = io.StringIO()
    writer = csv.writer(out, lineterminator="\n")
    measures = ("right", "accept_when_wrong", "reject_when_right")
    writer.writerow(
        ["label", "user_trust", "grouping", "group", "cases"]
        + [f"{m}{suffix}" for m in measures for suffix in ("", "_low", "_high", "_n")]
    )
    for item in metrics:
        overall = GroupRow(
            group="all",
            cases=sum(row.cases for row in item.by_kind),
            right=_overall_right(item),
            accepted=wilson(
                sum(row.accepted.hits for row in item.by_kind), sum(row.cases for row in item.by_kind)
            ),
            accept_when_wrong=item.accept_when_wrong,
            reject_when_right=item.reject_when_right,
        )
        groups = [("all", overall)] + [
            (grouping, row)
            for grouping, rows in (("kind", item.by_kind), ("app", item.by_app), ("tag", item.by_tag))
            for row in rows
        ]
        for grouping, row in groups:
            cells: list[object] = [item.label, item.user_trust, grouping, row.group, row.cases]
            for measure in measures:
                rate: Rate = getattr(row, measure)
                cells.extend([_number(rate.value), _number(rate.low), _number(rate.high), rate.total])
            writer.writerow(cells)
    return out.getvalue()


def _overall_right(item: CalibrationMetrics) -> Rate:
    hits = sum(row.right.hits for row in item.by_kind)
    return wilson(hits, sum(row.right.total for row in item.by_kind))


def _number(value: float | None) -> str:
    return "" if value is None else f"{value:.4f}"


def render_json(metrics: Sequence[CalibrationMetrics]) -> str:
    """Every measure of every calibrated user, as JSON."""
    return json.dumps([item.model_dump(mode="json") for item in metrics], indent=2, ensure_ascii=False) + "\n"
