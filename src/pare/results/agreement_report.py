"""``pare agreement``'s table in the report formats: terminal, Markdown, LaTeX, CSV and JSON."""

from __future__ import annotations

import csv
import io
import json
from collections.abc import Sequence

from rich.console import Console
from rich.table import Table

from pare.results.agreement import Agreement
from pare.results.report import LATEX_SPECIALS, format_percent
from pare.terminal_text import plain_text

TITLE = "Agreement with people"
NOTE = (
    "Each person's last verdict on an item against the user simulator's answer to the proposal (user) or "
    "the judge's verdict on the text (judge). Cohen's kappa with a percentile bootstrap interval over items; "
    "n/a where it is undefined (one side gave one verdict only)."
)
COLUMNS = (
    "Configuration",
    "Rater",
    "Items",
    "People",
    "Pairs",
    "Agree",
    "Kappa",
    "Interval",
    "Both yes",
    "Person only",
    "Machine only",
    "Both no",
    "Unanswered",
)
RATER_NAMES = {"user": "user simulator", "judge": "judge"}


def _number(value: float | None) -> str:
    return "n/a" if value is None else f"{value:.2f}"


def _interval(row: Agreement) -> str:
    return "n/a" if row.kappa_ci is None else f"[{row.kappa_ci[0]:.2f}, {row.kappa_ci[1]:.2f}]"


def _cells(row: Agreement) -> tuple[str, ...]:
    return (
        row.label,
        RATER_NAMES[row.rater],
        str(row.items),
        str(row.annotators),
        str(row.pairs),
        format_percent(row.observed),
        _number(row.kappa),
        _interval(row),
        str(row.both_positive),
        str(row.person_only),
        str(row.machine_only),
        str(row.both_negative),
        str(row.unanswered),
    )


def render_terminal(rows: Sequence[Agreement], console: Console) -> None:
    """Print the table (every cell as plain text: labels come from run folders)."""
    if not rows:
        console.print("No annotations to compare: mark proposals and judged texts in pare view first.")
        return
    table = Table(title=TITLE, caption=NOTE, title_justify="left", caption_justify="left")
    for index, column in enumerate(COLUMNS):
        table.add_column(column, justify="left" if index < 2 else "right")
    for row in rows:
        table.add_row(*(plain_text(cell) for cell in _cells(row)))
    console.print(table)


def render_markdown(rows: Sequence[Agreement]) -> str:
    """A ``##`` heading, the note and a pipe table."""
    lines = [f"## {TITLE}", "", NOTE, "", _markdown_row(COLUMNS)]
    lines.append("|" + "|".join(":---" if i < 2 else "---:" for i in range(len(COLUMNS))) + "|")
    lines += [_markdown_row(_cells(row)) for row in rows]
    return "\n".join(lines) + "\n"


def _markdown_row(cells: Sequence[str]) -> str:
    return "| " + " | ".join(cell.replace("|", "\\|").replace("\n", " ") for cell in cells) + " |"


def _latex(text: str) -> str:
    return "".join(LATEX_SPECIALS.get(char, char) for char in text)


def render_latex(rows: Sequence[Agreement]) -> str:
    """A booktabs ``table`` environment whose caption is the note."""
    align = "ll" + "r" * (len(COLUMNS) - 2)
    lines = [
        "\\begin{table}[ht]",
        "\\centering",
        f"\\begin{{tabular}}{{{align}}}",
        "\\toprule",
        " & ".join(rf"\textbf{{{_latex(column)}}}" for column in COLUMNS) + r" \\",
        "\\midrule",
        *(" & ".join(_latex(cell) for cell in _cells(row)) + r" \\" for row in rows),
        "\\bottomrule",
        "\\end{tabular}",
        f"\\caption{{{_latex(TITLE)}. {_latex(NOTE)}}}",
        "\\label{tab:pare-agreement}",
        "\\end{table}",
    ]
    return "\n".join(lines) + "\n"


def render_csv(rows: Sequence[Agreement]) -> str:
    """One row per configuration and rater: every field, the interval as ``kappa_ci_low``/``_high``."""
    fields = [name for name in Agreement.model_fields if name != "kappa_ci"]
    columns = [*fields, "kappa_ci_low", "kappa_ci_high"]
    buffer = io.StringIO()
    writer = csv.DictWriter(buffer, fieldnames=columns, lineterminator="\n")
    writer.writeheader()
    for row in rows:
        data = {name: "" if getattr(row, name) is None else str(getattr(row, name)) for name in fields}
        low, high = row.kappa_ci or (None, None)
        data["kappa_ci_low"] = "" if low is None else str(low)
        data["kappa_ci_high"] = "" if high is None else str(high)
        writer.writerow(data)
    return buffer.getvalue()


def render_json(rows: Sequence[Agreement]) -> str:
    """``{"agreement": [...]}``, sorted keys, indent 2."""
    data = {"agreement": [row.model_dump(mode="json") for row in rows]}
    return json.dumps(data, indent=2, sort_keys=True, ensure_ascii=False) + "\n"
