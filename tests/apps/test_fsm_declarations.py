"""Sweep every registered app: declarations are complete, drawable, and hold when walked."""

from __future__ import annotations

import random
from collections import Counter

import pytest

from pare.apps.fsm import to_mermaid, transitions
from pare.apps.registry import app_names, get_app_class
from pare.apps.sample_data import sample_world
from pare.apps.screens import BACK, STAY
from pare.env.random_walk import RandomUser
from tests.conftest import make_env

APPS = app_names()


@pytest.mark.parametrize("name", APPS)
def test_every_tool_and_action_is_documented_for_models(name: str) -> None:
    cls = get_app_class(name)
    assert cls.screens, f"{name} has no screens"
    specs = list(cls.tools.values()) + [s for screen in cls.screens for s in screen.actions.values()]
    for spec in specs:
        assert len(spec.summary) > 10, spec.name
        for field in spec.params.model_fields.values():
            assert field.description, f"{name}.{spec.name}: undocumented argument"
        schema = spec.function_schema()
        assert schema["function"]["parameters"]["additionalProperties"] is False


@pytest.mark.parametrize("name", APPS)
def test_agent_api_has_reads_and_writes(name: str) -> None:
    kinds = Counter(spec.kind for spec in get_app_class(name).tools.values())
    assert kinds["read"] > 0 and kinds["write"] > 0


@pytest.mark.parametrize("name", APPS)
def test_mermaid_export_matches_the_declarations(name: str) -> None:
    cls = get_app_class(name)
    text = to_mermaid(cls)
    assert text.startswith("stateDiagram-v2\n")
    assert f"[*] --> {cls.screens[0].screen_name()}" in text
    for screen in cls.screens:
        for spec in screen.actions.values():
            if STAY in spec.leads_to:
                assert f"    {screen.screen_name()} : {spec.name}\n" in text
            for target in spec.leads_to:
                if target not in (STAY, BACK):
                    assert f"    {screen.screen_name()} --> {target} : {spec.name}\n" in text
    for edge in transitions(cls):
        assert edge.target in {s.screen_name() for s in cls.screens}
    reachable = {cls.screens[0].screen_name()} | {edge.target for edge in transitions(cls)}
    assert reachable == {s.screen_name() for s in cls.screens}, "every screen is reachable from the root"


def test_random_walk_reaches_every_screen_and_action_without_breaking_a_declaration() -> None:
    env = make_env(APPS, sample_world(), seed=1)
    user = RandomUser(random.Random(1))
    for _ in range(15_000):  # about 1,500 steps per app
        user.step(env)  # raise_internal_errors: any undeclared transition or crash fails the test
    seen_screens = {e.app_screen for e in env.log if e.app_screen}
    tried = {(e.app, e.tool) for e in env.log if e.actor == "user"}
    for name in APPS:
        cls = get_app_class(name)
        assert {(name, s.screen_name()) for s in cls.screens} <= seen_screens, name
        for screen in cls.screens:
            for action in screen.actions:
                assert (name, action) in tried, f"the walk never tried {name}.{action}"
    assert sum(e.ok for e in env.log) / len(env.log) > 0.7
