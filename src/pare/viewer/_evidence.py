"""Which log entries decided each check, matched again with the scenario's own patterns.

A check's sentence names the entries it found only when it failed on them (a judge check names the texts
it read); to link every verdict to its entries the viewer matches the check's action pattern against the
trajectory's log once more, and evaluates each state check's ``where`` once more to link the calls that
made the very items it found (the final state is the scenario's start with the episode's state diff
applied). That needs the very scenario the episode ran: the library's copy is used only when its content
hash is the one the episode recorded. Otherwise (a scenario file given by path, or changed since) the
page falls back to what the sentence and the attribution tell.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from pare.errors import UserInputError
from pare.results.run_folder import scenario_hash
from pare.results.trajectory import Trajectory
from pare.results.trajectory import final_state as apply_diff
from pare.scenarios.build import build_environment
from pare.scenarios.checks import state_check_places
from pare.scenarios.file_identity import FileIdentity
from pare.scenarios.library import get_scenario
from pare.scenarios.model import ActionPattern, Scenario
from pare.scenarios.patterns import CompiledPattern
from pare.scenarios.reading import CallReader
from pare.viewer._credit import Credits

CheckKey = tuple[str, int]
"""A check by goal id and position."""


def library_scenario(scenario_id: str, wanted_hash: str) -> Scenario | None:
    """The library's scenario ``scenario_id`` if its content is the one an episode ran, else ``None``."""
    try:
        scenario = get_scenario(scenario_id)
    except UserInputError:
        return None
    return scenario if scenario_hash(scenario) == wanted_hash else None


def matched_entries(
    scenario: Scenario, trajectory: Trajectory, final: Mapping[str, Any] | None = None
) -> dict[CheckKey, list[int]]:
    """For each action, forbidden-action and judge check: the entries its pattern matches (for a judge
    check, those with a text to read; for an action check that found none, the calls of the tool it
    wanted). State checks are left out. The episode's ``final`` state, when known, tells whom each call
    told and which files it carried (patterns with ``to`` match nothing without it).
    """
    entries = trajectory.log_entries()
    reader = None if final is None else CallReader.of_state(lambda: final, FileIdentity.of(scenario))
    found: dict[CheckKey, list[int]] = {}
    for goal in scenario.goals:
        for index, check in enumerate(goal.checks):
            pattern: ActionPattern | None = check.action or check.no_action
            if check.judge is not None:
                pattern = check.judge.action
            if pattern is None:
                continue
            compiled = CompiledPattern.of(pattern, scenario.start)
            hits = compiled.find(entries, reader)
            if check.judge is not None:  # the judge reads only the calls that carry a text
                field = check.judge.field
                hits = [e for e in hits if isinstance(compiled.arguments(e, reader).get(field), str)]
            if not hits and check.action is not None:
                hits = [entry for entry in entries if compiled.matches_call(entry)]
            found[(goal.id, index)] = [entry.index for entry in hits]
    return found


def state_entries(
    scenario: Scenario, trajectory: Trajectory, final: dict[str, Any] | None = None
) -> dict[CheckKey, list[int]]:
    """For each state check: the calls that made the items it found (or the value it read) in the
    episode's final state (``final``, or :func:`final_state` worked out here). Empty when the trajectory
    has no diff or the diff does not apply to the start.
    """
    final = final if final is not None else final_state(scenario, trajectory)
    if final is None:
        return {}
    credits = Credits(trajectory.log, trajectory.marks)
    return {
        key: sorted({index for place in places for index in credits.made(place)})
        for key, places in state_check_places(scenario, final).items()
    }


def final_state(scenario: Scenario, trajectory: Trajectory) -> dict[str, Any] | None:
    """An episode's final state: the scenario's start with the trajectory's state diff applied (``None``
    when the trajectory has no diff, or the start is not the one the episode had, or the diff does not
    apply to it).
    """
    start = build_environment(scenario).snapshot(shared=True)
    try:
        return apply_diff(trajectory, start)
    except ValueError:
        return None
