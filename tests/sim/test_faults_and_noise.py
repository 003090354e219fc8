"""Tool-failure injection and noise: rates match their settings, draws come from the seed."""

from __future__ import annotations

import math
import random
from datetime import timedelta

import pytest

from pare.sim import NoiseStream, ToolFailureInjector, default_corpus
from tests.conftest import START, err, make_env, ok
from tests.fixture_app import NotebookApp


def within(observed: int, trials: int, probability: float, sigmas: float = 4.0) -> bool:
    expected = trials * probability
    return abs(observed - expected) <= sigmas * math.sqrt(trials * probability * (1 - probability))


@pytest.mark.parametrize("probability", [0.1, 0.2, 0.4])
def test_assistant_failure_rate_matches_p(probability: float) -> None:
    env = make_env([NotebookApp()], seed=7, tool_failure_probability=probability)
    trials = 4000
    for _ in range(trials):
        env.call("assistant", "notebook__list_items", {}, mode="observe")
    failures = sum(1 for e in env.log if e.injected_failure)
    assert within(failures, trials, probability), failures


def test_injected_failures_are_transient_logged_and_change_nothing() -> None:
    env = make_env([NotebookApp()], seed=3, tool_failure_probability=1.0)
    result = env.call("assistant", "notebook__add_item", {"text": "x"}, mode="execute")
    err(result, "transient error", "retry")
    assert env.log[-1].injected_failure
    assert env.app("notebook").state.items == {}


def test_only_assistant_app_tools_fail() -> None:
    env = make_env([NotebookApp()], seed=3, tool_failure_probability=1.0)
    ok(env.call("user", "open_app", {"app_name": "notebook"}))
    ok(env.call("user", "show"))
    ok(env.call("env", "notebook__arrive", {"text": "x"}))
    ok(env.call("assistant", "system__get_current_time", {}, mode="observe"))
    ok(env.call("assistant", "agent_ui__send_message_to_user", {"content": "Add milk?"}, mode="observe"))


def test_invalid_calls_fail_as_invalid_not_as_injected() -> None:
    env = make_env([NotebookApp()], seed=3, tool_failure_probability=1.0)
    err(env.call("assistant", "notebook__add_item", {}, mode="execute"), "missing required argument")
    assert not env.log[-1].injected_failure


def test_failure_decisions_follow_the_seed() -> None:
    def pattern(seed: int) -> list[bool]:
        injector = ToolFailureInjector(0.5, random.Random(seed))
        return [injector.draw("a", "b") is not None for _ in range(64)]

    assert pattern(1) == pattern(1)
    assert pattern(1) != pattern(2)


def test_failure_probability_out_of_range_is_refused() -> None:
    with pytest.raises(ValueError, match="within"):
        ToolFailureInjector(1.5, random.Random(0))


def stream(
    rate: float, seed: int = 0, apps: frozenset[str] = frozenset({"email", "messaging"})
) -> NoiseStream:
    return NoiseStream(
        rate_per_minute=rate,
        start=START,
        apps=set(apps),
        arrivals=random.Random(seed),
        contents=random.Random(seed + 1),
    )


@pytest.mark.parametrize("rate", [2.0, 4.0, 6.0])
def test_noise_arrival_rate_matches_r(rate: float) -> None:
    noise = stream(rate, seed=11)
    horizon = START + timedelta(minutes=300)
    count = 0
    while noise.next_time is not None and noise.next_time <= horizon:
        noise.pop()
        count += 1
    expected = rate * 300
    assert abs(count - expected) <= 4 * math.sqrt(expected), count


def test_noise_does_not_repeat_within_an_episode() -> None:
    noise = stream(6.0, seed=5)
    items = [noise.pop() for _ in range(3000)]
    assert len({(a.action.app, *a.action.args.values()) for a in items}) == 3000
    assert [a.time for a in items] == sorted(a.time for a in items)
    assert {a.action.tool for a in items} == {"receive_email", "receive_message"}


def test_noise_only_for_apps_present() -> None:
    noise = stream(6.0, apps=frozenset({"messaging", "contacts"}))
    assert {noise.pop().action.app for _ in range(100)} == {"messaging"}
    assert stream(6.0, apps=frozenset({"contacts"})).next_time is None


def test_noise_off_means_no_arrivals() -> None:
    assert stream(0.0).next_time is None


def test_corpus_placeholders_all_resolve() -> None:
    corpus = default_corpus()
    assert len(corpus.apps["email"]) >= 50 and len(corpus.apps["messaging"]) >= 40
    for templates in corpus.apps.values():
        for template in templates:
            for text in template.fields.values():
                for name in __import__("string").Formatter().parse(text):
                    if name[1]:
                        assert name[1].split("[")[0] in corpus.slots, (template.kind, text)


def test_noise_does_not_keep_an_episode_alive() -> None:
    env = make_env([NotebookApp()], noise_rate_per_minute=5.0)
    assert env.next_event_time() is None


def test_features_that_are_off_never_draw_and_leave_the_others_draws_alone() -> None:
    """With failures off, noise draws exactly what it draws with failures on (streams are per feature);
    a draw from the stream handed to a feature that is off is a bug, and raises.
    """
    from pare.errors import SimulationBug
    from pare.sim.rng import UNUSED_STREAM

    def noise_times(failures: float) -> list[object]:
        env = make_env(
            ["email", "messaging"], seed=3, noise_rate_per_minute=0.5, tool_failure_probability=failures
        )
        env.advance(timedelta(hours=2))
        return [entry.time for entry in env.log if entry.actor == "env"]

    assert noise_times(0.0) == noise_times(0.3) != []
    with pytest.raises(SimulationBug, match="feature that is off"):
        UNUSED_STREAM.random()
    with pytest.raises(SimulationBug, match="feature that is off"):
        UNUSED_STREAM.choice(["a", "b"])
    quiet = make_env([NotebookApp()], seed=3)
    for _ in range(50):
        assert quiet.call("assistant", "notebook__list_items", {}, mode="observe").ok
