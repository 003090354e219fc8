"""Episodes of one scenario share what is worked out once (the validated seed, compiled events) but never
anything an episode can change: one episode's writes never show in the next one's world.
"""

from __future__ import annotations

import gc
import weakref
from datetime import timedelta
from typing import Any

import pytest
from pydantic import BaseModel

from pare.apps.base import App
from pare.apps.screens import Screen, action
from pare.env import EnvConfig, Environment
from pare.errors import SimulationBug, UserInputError
from pare.scenarios import Scenario, build_environment
from pare.scenarios.library import library
from tests.scenarios.helpers import base, fair, parse


def _scenario() -> Scenario:
    data: dict[str, Any] = fair()
    data["events"][0]["args"]["recipients"] = ["me@pare.example"]  # a list inside an event's arguments
    return parse(data)


def test_one_episode_s_writes_never_show_in_the_next() -> None:
    scenario = _scenario()
    first = build_environment(scenario, EnvConfig(seed=1))
    pristine = first.snapshot()
    # a write through the tools, one straight into the state, and events fired with their arguments
    assert first.call(
        "oracle", "email__send_email", {"recipients": ["x@y.z"], "subject": "s", "content": "c"}
    ).ok
    first.apps["calendar"].state.events["ev1"].title = "Changed in place"
    first.advance(timedelta(minutes=10))
    fired = next(entry for entry in first.log if entry.event_id == "ann_asks")
    fired.args["recipients"].append("someone-else@x.example")
    assert first.snapshot() != pristine

    second = build_environment(scenario, EnvConfig(seed=2))
    assert second.snapshot() == pristine
    second.advance(timedelta(minutes=10))
    fired_again = next(entry for entry in second.log if entry.event_id == "ann_asks")
    assert fired_again.args["recipients"] == ["me@pare.example"]
    for app in ("email", "calendar"):
        assert second.apps[app].state is not first.apps[app].state


def test_a_reactive_event_is_bound_to_its_own_episode() -> None:
    """The compiled trigger is shared; what it reads (the log, what still waits) is the episode's own."""
    scenario = _scenario()
    first = build_environment(scenario)
    second = build_environment(scenario)
    first.advance(timedelta(minutes=6))
    reply = {"email_id": "e_ann", "content": "Thursday works!"}
    assert first.call("assistant", "email__reply_to_email", reply, mode="execute").ok
    first.advance(timedelta(minutes=10))
    assert "ann_confirms" in first.scheduler.completed
    assert second.scheduler.waiting_on_conditions == ["ann_confirms", "ann_confirms_otherwise"]
    second.advance(timedelta(minutes=6))
    assert second.call(
        "assistant", "email__reply_to_email", {**reply, "content": "Friday?"}, mode="execute"
    ).ok
    second.advance(timedelta(minutes=10))
    assert "ann_confirms_otherwise" in second.scheduler.completed
    assert "ann_confirms" not in second.scheduler.completed


def test_later_episodes_start_from_the_same_world_as_the_first() -> None:
    """The first build validates the seed; later ones copy what it loaded: the same state, field for field."""
    for scenario in library().values():
        copy = scenario.model_copy()  # a fresh object: its first build validates the seed
        first, later = build_environment(copy), build_environment(copy)
        assert later.snapshot() == first.snapshot(), scenario.id
        assert later.scheduler.waiting_on_conditions == first.scheduler.waiting_on_conditions, scenario.id
        assert later.next_event_time() == first.next_event_time(), scenario.id


def test_a_broken_seed_is_refused_by_every_build() -> None:
    data = base()
    data["seed"]["calendar"]["events"][0]["start_datetime"] = "not a time"
    scenario = parse(base()).model_copy(update={"seed": data["seed"]})
    for _ in range(2):
        with pytest.raises(UserInputError, match="calendar"):
            build_environment(scenario)


def test_an_app_only_adopts_its_own_state() -> None:
    env = build_environment(parse(base()))
    with pytest.raises(SimulationBug, match="not its State"):
        env.apps["email"].adopt(env.apps["calendar"].state)


class _NoData(BaseModel):
    pass


class _Clashing(Screen):
    name = "Clashing"

    @action()
    def go_home(self, app: App) -> str:
        """Pretend to go home, hiding the shell's go_home.

        Returns:
            nothing useful.
        """
        return "no"


class _ClashingApp(App):
    """An app whose screen hides a shell tool."""

    name = "clashing"
    title = "Clashing"
    State = _NoData


_ClashingApp.set_screens(_Clashing)


def test_a_screen_redefining_a_shell_tool_is_refused_every_time() -> None:
    """The check is made once per app class, and made again for a class that failed it."""
    for _ in range(2):
        with pytest.raises(SimulationBug, match="redefines shell tools"):
            Environment([_ClashingApp()])


def test_an_episode_s_world_is_freed_as_soon_as_it_is_dropped() -> None:
    """Nothing in an episode's world refers back to it (apps reach their siblings through a weak view,
    triggers read the log only), so it is freed when dropped, not left for the cyclic collector."""
    scenario = _scenario()
    build_environment(scenario)  # the blueprint, made once
    collecting = gc.isenabled()
    gc.disable()
    try:
        env = build_environment(scenario)
        env.advance(timedelta(minutes=6))
        reply = {"email_id": "e_ann", "content": "Friday?"}
        assert env.call("assistant", "email__reply_to_email", reply, mode="execute").ok
        env.advance(timedelta(minutes=10))
        assert "ann_confirms_otherwise" in env.scheduler.completed
        pieces = [weakref.ref(env), weakref.ref(env.apps["email"]), weakref.ref(env.notifications)]
        del env
        assert [piece() for piece in pieces] == [None, None, None]
    finally:
        if collecting:
            gc.enable()


def test_an_app_outliving_its_environment_says_so() -> None:
    shell = Environment(["email"]).system
    with pytest.raises(SimulationBug, match="environment was discarded"):
        shell.openable_apps()


def test_an_app_builds_its_data_only_when_read_and_reports_the_same() -> None:
    """An episode that never reads an app's data reports its seed's snapshot, shared and unchanged; one
    that reads it gets its own copy, and ``snapshot()`` always hands the caller data of its own.
    """
    scenario = _scenario()
    build_environment(scenario)  # the first build makes the scenario's blueprint
    env = build_environment(scenario)
    calendar = env.apps["calendar"]
    assert "state" not in vars(calendar)  # not built yet
    shared = env.snapshot(shared=True)
    assert shared["calendar"] is build_environment(scenario).snapshot(shared=True)["calendar"]
    own = env.snapshot()
    assert own == shared and own["calendar"] is not shared["calendar"]
    own["calendar"]["events"].clear()  # the caller's own data: nothing else sees this
    assert env.snapshot(shared=True)["calendar"] == env.snapshot()["calendar"] != own["calendar"]

    calendar.state.events["ev1"].title = "Changed in place"  # a read builds the episode's own copy
    assert env.snapshot(shared=True)["calendar"]["events"]["ev1"]["title"] == "Changed in place"
    assert build_environment(scenario).snapshot(shared=True) == shared


def test_episodes_never_change_the_snapshots_they_share() -> None:
    """Every library scenario played twice by the oracle: the seed snapshots its episodes shared (start
    state, checks, state diff, attribution) are still what the seed states give.
    """
    from pare.bench import run_episode
    from pare.scenarios import OracleAssistant, OracleUser

    scenarios = list(library().values())
    for scenario in scenarios:
        for _ in range(2):
            run_episode(scenario, OracleUser(scenario), OracleAssistant(scenario))
    for scenario in scenarios:
        env = build_environment(scenario)
        for name, app in env.apps.items():
            seed = app._seed
            if seed is not None:
                assert seed.snapshot == app.state.model_dump(mode="json"), (scenario.id, name)
