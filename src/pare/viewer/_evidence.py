"""Which log entries decided each check, asked again of the scenario's own checks.

A check's sentence names the entries it found only when it failed on them (a judge check names the texts
it read); to link every verdict to its entries the viewer asks each check's rule (its form's, see
:data:`pare.scenarios.checks.CHECK_FORMS`) which entries of the trajectory's log decided it, and where in
the final state a state check found what it counted, to link the calls that made the very items it found
(the final state is the scenario's start with the episode's state diff applied). That needs the very
scenario the episode ran: the library's copy is used only when its content hash is the one the episode
recorded. Otherwise (a scenario file given by path, or changed since) the page falls back to what the
sentence and the attribution tell.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from pare.errors import UserInputError
from pare.results.run_folder import scenario_hash
from pare.results.trajectory import Trajectory
from pare.results.trajectory import final_state as apply_diff
from pare.scenarios.build import build_environment
from pare.scenarios.checks import linked_entries, state_check_places
from pare.scenarios.library import get_scenario
from pare.scenarios.model import Scenario
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
    """For each check that reads the action log: the entries that decided it, as its form's rule says
    (:func:`pare.scenarios.checks.linked_entries`). State checks are left out (:func:`state_entries`).
    The episode's ``final`` state, when known, tells whom each call told and which files it carried.
    """
    return linked_entries(scenario, trajectory.log_entries(), final)


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
