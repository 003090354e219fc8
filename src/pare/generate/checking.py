"""The gate as far as a candidate has got: after each stage, load it and play the runs it can play.

* story: the story's fields load, the chosen apps, tags and difficulty are kept, the id is free;
* seed: the seed data loads, and the world built from it plays (the ``nothing`` run);
* events: the oracle, the slow user and the user by hand are played (their goals are still placeholders,
  so only failed calls and events, a proposal that never came and reactions that never fired count);
* validation: the whole gate, every run and variant.
"""

from __future__ import annotations

from collections.abc import Collection, Mapping
from dataclasses import dataclass

from pare.bench.episode import EpisodeSettings
from pare.bench.selftest import ScenarioVerdict, check_scenario
from pare.generate.config import GenerateConfig
from pare.generate.quoting import describe_problem
from pare.generate.sections import STAGE_KEYS, STAGES, assemble, top_key
from pare.scenarios.loader import ScenarioError, parse_scenario
from pare.scenarios.model import Scenario
from pare.scenarios.problem_groups import group_problems

SOURCE = "candidate.yaml"
_PLACEHOLDER_GOAL_LINES = ("check failed: placeholder", "goal 'placeholder'")
EARLY_RUNS: dict[str, tuple[str, ...]] = {
    "seed": ("nothing",),
    "events": ("oracle", "slow_user", "by_hand"),
}
"""The runs played after the seed and events stages, before any goal is written (their verdicts mean
nothing yet: only their own problems count, such as a world that cannot be built or a failed call)."""


@dataclass(frozen=True, slots=True)
class StageCheck:
    """What the gate found after one stage: the problems (none: the stage is done) and, when it got that
    far, the loaded scenario and the gate's verdict.
    """

    problems: tuple[str, ...]
    played: bool
    scenario: Scenario | None = None
    verdict: ScenarioVerdict | None = None

    @property
    def turns(self) -> str:
        """The turns the played runs took against the limit (empty when nothing was played)."""
        return turns_taken(self.verdict) if self.verdict is not None else ""


SLACK_RUNS: dict[str, str] = {
    "oracle": "the oracle",
    "slow_user": "the slow user (an extra step before each of the user's)",
    "busy_user": "the busy user",
}
"""The runs whose turns the slack rule is about, as the generator is told them."""


def turns_taken(verdict: ScenarioVerdict) -> str:
    """One sentence: the turns each slack run took, of the episode's limit, so the slack can be judged."""
    limit = EpisodeSettings().max_turns
    taken = [
        f"{SLACK_RUNS[run.run]} {run.turns}"
        for run in verdict.runs
        if run.run in SLACK_RUNS and run.turns is not None
    ]
    if not taken:
        return ""
    return f"Turns taken, of the {limit} an episode has: {', '.join(taken)}."


def written_keys(stage: str) -> set[str]:
    """The top-level keys written by ``stage`` and the stages before it."""
    return {key for done in STAGES[: STAGES.index(stage) + 1] for key in STAGE_KEYS[done]}


def load_partial(sections: Mapping[str, str], stage: str) -> tuple[Scenario | None, list[str]]:
    """Load the candidate as far as ``stage`` (placeholders for the rest); problems in placeholders are
    left out.
    """
    keys = written_keys(stage)
    text = assemble(sections, placeholders=stage != STAGES[-1])
    try:
        return parse_scenario(text, source=SOURCE), []
    except ScenarioError as error:
        written = [problem for problem in error.problems if top_key(problem.path) in keys or not problem.path]
        # only the placeholders are wrong: nothing the stage can fix, so say it whole
        groups = group_problems(written or error.problems)
        return None, [describe_problem(group, text, sections) for group in groups]


def check_stage(
    stage: str,
    sections: Mapping[str, str],
    config: GenerateConfig,
    *,
    taken_ids: Collection[str] = (),
) -> StageCheck:
    """Load the candidate after ``stage`` and play the gate's runs it can play."""
    scenario, problems = load_partial(sections, stage)
    if scenario is None:
        return StageCheck(tuple(problems), played=False)
    if stage == "story":
        return StageCheck(tuple(_story_problems(scenario, config, taken_ids)), False, scenario)
    if stage in EARLY_RUNS:
        verdict = check_scenario(scenario, runs=EARLY_RUNS[stage], variants=False)
        lines = [
            f"[{run.run}] {line}"
            for run in verdict.runs
            for line in run.problems
            if not line.startswith(_PLACEHOLDER_GOAL_LINES)
        ]
        return StageCheck(tuple(lines), True, scenario, verdict)
    verdict = check_scenario(scenario)
    warnings = [f"{line} (a warning the library does not accept either: fix it)" for line in verdict.warnings]
    return StageCheck((*verdict.breaches(), *warnings), True, scenario, verdict)


def _story_problems(scenario: Scenario, config: GenerateConfig, taken_ids: Collection[str]) -> list[str]:
    problems = []
    missing = [app for app in config.apps if app not in scenario.apps]
    if missing:
        problems.append(f"apps: the scenario must use {', '.join(config.apps)}; missing {', '.join(missing)}")
    if config.tags and not set(config.tags) & set(scenario.tags):
        problems.append(f"tags: include at least one of {', '.join(config.tags)}")
    if config.difficulty and scenario.difficulty not in config.difficulty:
        problems.append(f"difficulty: must be one of {', '.join(config.difficulty)}")
    if scenario.id in taken_ids:
        problems.append(f"id: '{scenario.id}' is taken by another scenario; choose another")
    return problems
