"""The episodes table: one plain row per episode record, and the choices each filter offers.

Rows are what the browser filters and sorts; they are written once per configuration as a small
script (``rows.js``) so the table works the same served and opened from disk.
"""

from __future__ import annotations

import json
from collections.abc import Iterable
from typing import Any

from pare.agents.models.ledger import RoleUsage
from pare.results.records import EpisodeRecord
from pare.viewer._paths import slug

FILTERS = ("scenario", "app", "tag", "difficulty", "success", "decision", "ended", "failures")
"""The table's filters, in the order the page shows them."""


def episode_href(record: EpisodeRecord) -> str:
    """The episode page, relative to its configuration's folder."""
    return f"e/{slug(record.scenario_id)}/run-{record.run}.html"


def failure_labels(record: EpisodeRecord) -> list[str]:
    """What went wrong in an episode apart from its verdict: not run (and why), failed steps and
    malformed answers per role, a user who did the work by hand, side effects of the assistant's, a
    verdict a re-grade changed.
    """
    labels = []
    if record.failure is not None:
        labels.append(f"not run: {record.failure.kind}")
    labels.extend(f"failed step: {role}" for role, count in sorted(record.failed_steps.items()) if count)
    labels.extend(
        f"malformed answer: {role}" for role, count in sorted(record.format_errors.items()) if count
    )
    if record.user_did_work:
        labels.append("user did the work")
    if record.side_effects:
        labels.append(f"side effects: {record.side_effects}")
    before = record.regraded_from
    if before is not None and (before.success != record.success or before.goals != record.goals):
        labels.append(f"re-graded: was {'success' if before.success else 'failure'}")
    return labels


def row(record: EpisodeRecord) -> dict[str, Any]:
    """One row of the episodes table."""
    total = RoleUsage()
    for usage in record.usage.values():
        total = total + usage
    cost = total.cost_usd
    return {
        "scenario": record.scenario_id,
        "run": record.run,
        "href": episode_href(record),
        "status": record.status,
        "success": "yes" if record.complete and record.success else ("no" if record.complete else "not run"),
        "goals": f"{sum(record.goals.values())}/{len(record.goals)}",
        "goal_rate": round(record.goal_rate, 4),
        "turns": record.turns,
        "ended": record.ended or record.status,
        "apps": list(record.apps),
        "tags": list(record.tags),
        "difficulty": record.difficulty or "unspecified",
        "proposals": len(record.proposals),
        "decisions": [proposal.decision for proposal in record.proposals] or ["no proposal"],
        "resolutions": [proposal.resolution for proposal in record.proposals],
        "failures": failure_labels(record) or ["none"],
        "tokens": total.total_tokens,
        "cost": None if cost is None else round(cost, 6),
        "cost_text": total.describe_cost() if total.calls else "",
        "read_actions": record.read_actions,
        "write_actions": record.write_actions,
    }


def rows(records: Iterable[EpisodeRecord]) -> list[dict[str, Any]]:
    """The table's rows, in the records' order."""
    return [row(record) for record in records]


def filter_choices(table: list[dict[str, Any]]) -> dict[str, list[str]]:
    """For each filter, the values present in the table, sorted."""
    columns = {"app": "apps", "tag": "tags", "decision": "decisions", "failures": "failures"}
    choices: dict[str, list[str]] = {}
    for name in FILTERS:
        column = columns.get(name, name)
        seen: set[str] = set()
        for item in table:
            value = item[column]
            seen.update(str(v) for v in (value if isinstance(value, list) else [value]))
        choices[name] = sorted(seen)
    return choices


def rows_script(cid: str, table: list[dict[str, Any]]) -> str:
    """``rows.js``: registers the table's rows under the configuration's id (a script, not JSON, so a
    page opened from disk can load it).
    """
    data = json.dumps(table, ensure_ascii=True, separators=(",", ":")).replace("</", "<\\/")
    key = json.dumps(cid)
    return f"window.PARE_ROWS = window.PARE_ROWS || {{}};\nwindow.PARE_ROWS[{key}] = {data};\n"
