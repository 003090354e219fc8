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
from datetime import datetime
from typing import Any

import jsonpatch

from pare.errors import UserInputError
from pare.results.run_folder import scenario_hash
from pare.scenarios.build import build_environment
from pare.scenarios.checks import linked_entries, state_check_places
from pare.scenarios.library import get_scenario
from pare.scenarios.model import Scenario
from pare.sim.log import LogEntry
from pare.viewer._credit import Credits
from pare.viewer._episode import episode_log

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
    scenario: Scenario, log: list[dict[str, Any]], final: Mapping[str, Any] | None = None
) -> dict[CheckKey, list[int]]:
    """For each check that reads the action log: the entries that decided it, as its form's rule says
    (:func:`pare.scenarios.checks.linked_entries`). State checks are left out (:func:`state_entries`).
    The episode's ``final`` state, when known, tells whom each call told and which files it carried.
    """
    try:
        entries = [_entry(item) for item in log]
    except (KeyError, TypeError, ValueError):  # a log this PARE cannot read back: no precise links
        return {}
    return linked_entries(scenario, entries, final)


def state_entries(
    scenario: Scenario, data: dict[str, Any], final: dict[str, Any] | None = None
) -> dict[CheckKey, list[int]]:
    """For each state check: the calls that made the items it found (or the value it read) in the
    episode's final state (``final``, or :func:`final_state` worked out here). Empty when the trajectory
    has no diff or the diff does not apply to the start.
    """
    final = final if final is not None else final_state(scenario, data)
    if final is None:
        return {}
    credits = Credits(episode_log(data), data.get("attribution") or {})
    return {
        key: sorted({index for place in places for index in credits.made(place)})
        for key, places in state_check_places(scenario, final).items()
    }


def final_state(scenario: Scenario, data: dict[str, Any]) -> dict[str, Any] | None:
    """An episode's final state: the scenario's start with the trajectory's state diff applied (``None``
    when the trajectory has no diff or it does not apply to the start).
    """
    diff = data.get("state_diff")
    if not isinstance(diff, list):
        return None
    start = build_environment(scenario).snapshot(shared=True)
    try:  # applied to a copy: the start snapshot is shared with every episode of the scenario
        final: dict[str, Any] = jsonpatch.apply_patch(start, diff)
    except (jsonpatch.JsonPatchException, jsonpatch.JsonPointerException, TypeError, KeyError):
        return None
    return final


def _entry(item: dict[str, Any]) -> LogEntry:
    return LogEntry(
        index=int(item["index"]),
        turn=int(item["turn"]),
        time=datetime.fromisoformat(str(item["time"])),
        actor=item["actor"],
        app=str(item["app"]),
        tool=str(item["tool"]),
        args=dict(item.get("args") or {}),
        kind=item.get("kind"),
        ok=bool(item["ok"]),
        result=item.get("result"),
        error=item.get("error"),
        mode=item.get("mode"),
        injected_failure=bool(item.get("injected_failure", False)),
        event_id=item.get("event_id"),
        screen=item.get("screen"),
    )
