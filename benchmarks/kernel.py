"""Kernel timings: the mean time of one tool dispatch per kind of call, and of a seeded random walk.

    python benchmarks/kernel.py [--steps 10000] [--seed 0]

Prints numbers only; no assertion. Each dispatch timing is the median of 5 repetitions of N calls.
"""

from __future__ import annotations

import argparse
import random
import statistics
import time
from collections.abc import Callable

from pare.apps.registry import app_names, get_app_class
from pare.apps.sample_data import START, sample_world
from pare.env import EnvConfig, Environment
from pare.env.random_walk import RandomAssistant, RandomUser

APPS = app_names()


def fresh_env(seed: int = 0) -> Environment:
    env = Environment(APPS, EnvConfig(seed=seed, start_time=START))
    env.load(sample_world())
    return env


def per_call_us(make: Callable[[Environment], Callable[[int], object]], calls: int = 2000) -> float:
    samples = []
    for _ in range(5):
        env = fresh_env()
        step = make(env)
        began = time.perf_counter()
        for i in range(calls):
            step(i)
        samples.append((time.perf_counter() - began) / calls * 1e6)
    return statistics.median(samples)


def assistant_read(env: Environment) -> Callable[[int], object]:
    return lambda i: env.call("assistant", "email__list_emails", {"limit": 5}, mode="observe")


def assistant_write(env: Environment) -> Callable[[int], object]:
    return lambda i: env.call(
        "assistant",
        "contacts__edit_contact",
        {"contact_id": "contact-bob", "updates": {"notes": str(i)}},
        mode="execute",
    )


def assistant_bad_call(env: Environment) -> Callable[[int], object]:
    return lambda i: env.call("assistant", "email__send_email", {"recipients": "x"}, mode="observe")


def user_screen_action(env: Environment) -> Callable[[int], object]:
    env.call("user", "open_app", {"app_name": "email"})
    return lambda i: env.call("user", "list_emails", {"limit": 5})


def user_shell_action(env: Environment) -> Callable[[int], object]:
    return lambda i: env.call(
        "user", "go_home" if i % 2 else "open_app", {} if i % 2 else {"app_name": "calendar"}
    )


def env_event(env: Environment) -> Callable[[int], object]:
    return lambda i: env.call(
        "env", "messaging__receive_message", {"sender": "Alice Chen", "content": f"ping {i}"}
    )


def random_walk(steps: int, seed: int) -> None:
    env = fresh_env(seed)
    user = RandomUser(random.Random(seed))
    in_env = 0.0
    began = time.perf_counter()
    for _ in range(steps):
        tool = user.choose(env)
        args = user.arguments(env, tool)
        call_began = time.perf_counter()
        env.call("user", tool.name, args)
        in_env += time.perf_counter() - call_began
    elapsed = time.perf_counter() - began
    screens = {e.app_screen for e in env.log if e.app_screen}
    total_screens = sum(len(get_app_class(name).screens) for name in APPS)
    actions = {(e.app, e.tool) for e in env.log if e.ok and e.actor == "user" and e.app in APPS}
    total_actions = sum(len(s.actions) for name in APPS for s in get_app_class(name).screens)
    succeeded = sum(e.ok for e in env.log) / len(env.log)
    print(f"random walk, {steps} steps over {len(APPS)} apps (seed {seed}):")
    print(
        f"  total {elapsed:.2f} s, mean {elapsed / steps * 1e6:.1f} us/step, of which the environment's "
        f"dispatch {in_env / steps * 1e6:.1f} us (the rest is the random policy choosing)"
    )
    print(
        f"  calls that succeeded: {succeeded:.1%}; screens reached: {len(screens)}/{total_screens}; "
        f"distinct screen actions that succeeded: {len(actions)}/{total_actions}"
    )


def assistant_walk(steps: int, seed: int) -> None:
    env = fresh_env(seed)
    assistant = RandomAssistant(random.Random(seed))
    in_env = 0.0
    began = time.perf_counter()
    for _ in range(steps):
        tool, args = assistant.choose(env)
        call_began = time.perf_counter()
        env.call("assistant", tool.name, args, mode="execute")
        in_env += time.perf_counter() - call_began
    elapsed = time.perf_counter() - began
    apps = sorted({e.app for e in env.log if e.ok})
    succeeded = sum(e.ok for e in env.log) / len(env.log)
    print(f"assistant random walk, {steps} calls over the flat API of {len(apps)} apps ({', '.join(apps)}):")
    print(
        f"  total {elapsed:.2f} s, mean {elapsed / steps * 1e6:.1f} us/call, of which the environment's "
        f"dispatch {in_env / steps * 1e6:.1f} us; calls that succeeded: {succeeded:.1%}"
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--steps", type=int, default=10_000)
    parser.add_argument("--seed", type=int, default=0)
    options = parser.parse_args()
    print("mean time of one tool dispatch (median of 5 x 2000 calls):")
    for label, make in [
        ("assistant read   email__list_emails", assistant_read),
        ("assistant write  contacts__edit_contact", assistant_write),
        ("assistant error  wrong mode + bad args", assistant_bad_call),
        ("user screen      list_emails on Mailbox", user_screen_action),
        ("user shell       open_app / go_home", user_shell_action),
        ("env event        messaging__receive_message", env_event),
    ]:
        print(f"  {label:<48} {per_call_us(make):8.1f} us")
    random_walk(options.steps, options.seed)
    assistant_walk(options.steps, options.seed)


if __name__ == "__main__":
    main()
