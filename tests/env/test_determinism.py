"""Same seed, same actions: the same action log, byte for byte."""

from __future__ import annotations

import json
import random
from datetime import timedelta

from pare.apps.registry import app_names
from pare.apps.sample_data import sample_world
from pare.env.random_walk import RandomUser
from pare.sim import AfterStart, EventAction, ScheduledEvent
from tests.conftest import make_env


def run(seed: int, steps: int = 400) -> str:
    env = make_env(
        app_names(),
        sample_world(),
        seed=seed,
        tool_failure_probability=0.3,
        noise_rate_per_minute=3.0,
    )
    hello = EventAction("messaging", "receive_message", {"sender": "Alice Chen", "content": "hi"})
    env.schedule(ScheduledEvent("e1", AfterStart(timedelta(minutes=7)), hello))
    user = RandomUser(random.Random(seed))
    assistant = random.Random(seed + 100)
    tools = [
        t.name
        for t in env.assistant_tools("observe")
        if t.spec.kind == "read" and not t.spec.parameters_schema["required"]
    ]
    for step in range(steps):
        user.step(env)
        env.call("assistant", assistant.choice(tools), {}, mode="observe")
        if step % 10 == 0:
            env.begin_turn()
            env.advance(timedelta(minutes=1))
    return json.dumps(env.log.to_list(), sort_keys=False) + json.dumps(env.snapshot(include_navigation=True))


def test_two_runs_with_one_seed_give_identical_logs() -> None:
    assert run(42) == run(42)


def test_another_seed_gives_another_run() -> None:
    assert run(42) != run(43)
