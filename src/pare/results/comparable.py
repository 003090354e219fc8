"""Whether runs may share one report: the same protocol preset, and the same version of every scenario
they have in common. Numbers from different protocols (whose metrics may be defined differently) or from
different versions of a scenario look comparable in one table and are not.
"""

from __future__ import annotations

from collections.abc import Sequence

from pare.protocols import manifest_protocol
from pare.results.run_folder import LoadedRun

SHOWN_SCENARIOS = 5
"""How many differing scenarios a problem names before it says how many more there are."""


def comparability_problems(runs: Sequence[LoadedRun]) -> list[str]:
    """What makes ``runs`` unfit to compare, one sentence each (empty: they may share a report)."""
    problems: list[str] = []
    by_preset: dict[str, list[str]] = {}
    for run in runs:
        preset, _ = manifest_protocol(run.manifest)
        by_preset.setdefault(preset, []).append(str(run.path))
    if len(by_preset) > 1:
        listed = "; ".join(f"{preset}: {', '.join(paths)}" for preset, paths in by_preset.items())
        problems.append(f"the runs played different protocol presets ({listed})")
    versions: dict[str, dict[str, str]] = {}  # scenario id -> its hash -> the first run that has it
    for run in runs:
        plan = run.manifest.get("plan")
        scenarios = plan.get("scenarios") if isinstance(plan, dict) else None
        if not isinstance(scenarios, dict):
            continue  # an old plan without hashes: nothing to compare
        for scenario_id, digest in scenarios.items():
            versions.setdefault(str(scenario_id), {}).setdefault(str(digest), str(run.path))
    changed = sorted(scenario_id for scenario_id, seen in versions.items() if len(seen) > 1)
    if changed:
        first = versions[changed[0]]
        shown = ", ".join(changed[:SHOWN_SCENARIOS])
        more = f" and {len(changed) - SHOWN_SCENARIOS} more" if len(changed) > SHOWN_SCENARIOS else ""
        problems.append(
            f"{len(changed)} scenario(s) differ between the runs ({shown}{more}; e.g. '{changed[0]}' "
            f"in {' and '.join(first.values())})"
        )
    return problems
