"""How much of what execute mode needs it is handed at its start, before and after the handover.

    python benchmarks/handover.py [PATHS ...]

For each scenario with a proposal (the library by default), the oracle plays both roles, and at each
accepted task this measures the ids the oracle's execute actions use (argument values that are ids of
items in the apps at the task's start) against what execute mode is given at its start:

* **before**: the proposal and the user's answer (all execute mode had before the handover);
* **after, seen**: plus the handover built from what observe mode was shown (the ids in the user's
  actions), which a model-backed assistant gets even if it reads nothing;
* **after, glance**: plus the handover of an observer that, before proposing, read every listing of
  the phone's apps (each observe read tool that needs no argument), as a diligent model would.

The glance's reads run on a copy of the phone, so the episode itself is the oracle's, unchanged.

It then estimates execute actions per task with a scripted executor that makes the oracle's actions and
needs one extra read for each distinct id it was not given, and counts the tasks that would not fit
execute mode's budget. Deterministic; prints numbers only, no assertion.
"""

from __future__ import annotations

import argparse
import copy
import re
import statistics
from collections.abc import Iterator
from dataclasses import dataclass, field
from typing import Any

from pare.agents.handover import Handover, is_id_key
from pare.agents.policy import SEND_MESSAGE, Action, Task
from pare.bench import run_episode
from pare.env import AssistantObservation, Environment, ToolResult
from pare.scenarios import OracleAssistant, OracleUser, load_scenarios
from pare.scenarios.model import Scenario
from pare.sim.budget import DEFAULT_BUDGET

LEVELS = ("before", "after, seen", "after, glance")


def ids_in(value: Any) -> Iterator[str]:
    """The string values under id keys anywhere in a JSON-ready ``value``."""
    if isinstance(value, dict):
        for key, item in value.items():
            if is_id_key(key) and isinstance(item, str):
                yield item
            else:
                yield from ids_in(item)
    elif isinstance(value, list):
        for item in value:
            yield from ids_in(item)


def strings_in(value: Any) -> Iterator[str]:
    """Every string in an action's arguments (ids may sit in lists: ``item_ids``)."""
    if isinstance(value, str):
        yield value
    elif isinstance(value, dict):
        for item in value.values():
            yield from strings_in(item)
    elif isinstance(value, list):
        for item in value:
            yield from strings_in(item)


def mentions(text: str, item_id: str) -> bool:
    """Whether ``text`` names ``item_id`` as a whole word (``e_ann`` is not in ``e_anna``)."""
    return re.search(rf"(?<![\w-]){re.escape(item_id)}(?![\w-])", text) is not None


def glance(env: Environment) -> list[ToolResult]:
    """What an observer reading every listing of the phone's apps would see now, on a copy of it."""
    phone = copy.deepcopy(env)
    results = []
    for tool in phone.assistant_tools("observe"):
        schema = tool.function_schema()["function"]["parameters"]
        if tool.name == SEND_MESSAGE or tool.name.startswith("system__") or schema.get("required"):
            continue
        results.append(phone.call("assistant", tool.name, {}, mode="observe"))
    return results


@dataclass
class TaskRecord:
    """One accepted task: the ids its actions use and what execute mode was given at its start."""

    scenario: str
    given: dict[str, str]
    """Per level, the text execute mode starts from."""
    known: set[str]
    """The ids of the items in the apps when the task started."""
    actions: list[Action] = field(default_factory=list)

    def used_ids(self) -> list[str]:
        """The distinct item ids the task's actions use, in order of first use."""
        used: dict[str, None] = {}
        for action in self.actions:
            for text in strings_in(action.args):
                if text in self.known:
                    used[text] = None
        return list(used)

    def missing(self, level: str) -> list[str]:
        return [item for item in self.used_ids() if not mentions(self.given[level], item)]


class MeasuredOracle(OracleAssistant):
    """The oracle assistant, recording at each accepted task what execute mode would be given."""

    def __init__(self, scenario: Scenario) -> None:
        super().__init__(scenario)
        self.seen = Handover()
        self.glanced = Handover()
        self.records: list[TaskRecord] = []
        self._proposal_glance: list[ToolResult] = []

    async def observe(self, observation: AssistantObservation | None, previous: ToolResult | None) -> Action:
        if observation is not None:
            for entry in [*observation.user_actions, *observation.executed]:
                self.seen.saw(entry)
                self.glanced.saw(entry)
        action = await super().observe(observation, previous)
        if action.tool == SEND_MESSAGE:
            for result in glance(self._env()):
                if result.entry is not None:
                    self.glanced.read(result.entry)
        return action

    async def execute(self, task: Task | None, previous: ToolResult | None) -> Action:
        if task is not None:
            env = self._env()
            told = f"{task.proposal}\n{task.answer}"
            self.records.append(
                TaskRecord(
                    scenario=self.scenario.id,
                    given={
                        "before": told,
                        "after, seen": f"{told}\n{self.seen.render()}",
                        "after, glance": f"{told}\n{self.glanced.render()}",
                    },
                    known=set(ids_in(env.snapshot())),
                )
            )
        action = await super().execute(task, previous)
        self.records[-1].actions.append(action)
        return action


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("paths", nargs="*", help="scenario files or directories (default: the library)")
    options = parser.parse_args()
    scenarios = [s for s in load_scenarios(options.paths or None) if s.solution().interventions]
    records: list[TaskRecord] = []
    for scenario in scenarios:
        assistant = MeasuredOracle(scenario)
        run_episode(scenario, OracleUser(scenario), assistant)
        records.extend(assistant.records)
    budget = DEFAULT_BUDGET.execute_steps
    used = sum(len(record.used_ids()) for record in records)
    oracle_actions = [len(record.actions) for record in records]
    print(f"scenarios with a proposal: {len(scenarios)}; accepted tasks: {len(records)}")
    print(f"item ids the oracle's execute actions use: {used} ({used / len(records):.2f} per task)")
    print(f"oracle execute actions per task (with the report): mean {statistics.mean(oracle_actions):.2f}")
    for level in LEVELS[1:]:
        sizes = [len(record.given[level]) - len(record.given["before"]) for record in records]
        print(f"handover ({level}): median {statistics.median(sizes):.0f} characters, max {max(sizes)}")
    print(
        f"{'given at the start':<16} {'ids given':>12} {'tasks missing none':>19} "
        f"{'actions/task':>13} {'over budget':>12}"
    )
    for level in LEVELS:
        missing = [len(record.missing(level)) for record in records]
        given = used - sum(missing)
        complete = sum(1 for count in missing if count == 0)
        actions = [n + extra for n, extra in zip(oracle_actions, missing, strict=True)]
        over = sum(1 for count in actions if count > budget)
        print(
            f"{level:<16} {given:>5}/{used:<6} {complete:>10}/{len(records):<8} "
            f"{statistics.mean(actions):>13.2f} {over:>8}/{len(records)}"
        )


if __name__ == "__main__":
    main()
