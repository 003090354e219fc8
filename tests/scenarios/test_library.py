"""The shipped PARE-Bench library: every file valid, every scenario through the gate, coverage kept."""

from __future__ import annotations

import json
from collections import Counter
from pathlib import Path

import pytest

from pare.apps.registry import phone_apps
from pare.bench import EpisodeSettings, run_episode
from pare.bench.selftest import check_scenario
from pare.env import EnvConfig
from pare.scenarios import TAGS, OracleAssistant, OracleUser, library, load_scenario, splits
from pare.scenarios.library import BENCH_DIR, scenario_files
from pare.scenarios.schema import SCHEMA_FILE, schema_text
from pare.scenarios.similarity import THRESHOLD, similarities
from pare.scenarios.stats import JUDGE_SHARE_MINIMUM, coverage

FILES = scenario_files()
IDS = [path.stem for path in FILES]


@pytest.mark.parametrize("path", FILES, ids=IDS)
def test_file_loads_and_points_editors_at_the_schema(path: Path) -> None:
    assert path.read_text(encoding="utf-8").startswith(
        "# yaml-language-server: $schema=../scenario.schema.json\n"
    )
    assert load_scenario(path).id == path.stem


@pytest.mark.parametrize("scenario_id", IDS)
def test_scenario_passes_the_gate_without_warnings(scenario_id: str) -> None:
    verdict = check_scenario(library()[scenario_id])
    assert verdict.ok, "\n".join(verdict.breaches())
    # a reply that fires on any message restates the answer to a wrong question
    assert not verdict.warnings, verdict.warnings


@pytest.mark.parametrize("scenario_id", IDS)
def test_oracle_is_deterministic_with_noise(scenario_id: str) -> None:
    scenario = library()[scenario_id]
    settings = EpisodeSettings(env=EnvConfig(seed=11, noise_rate_per_minute=1.0))

    def trajectory() -> str:
        result = run_episode(scenario, OracleUser(scenario), OracleAssistant(scenario), settings)
        return json.dumps(result.to_dict(), sort_keys=True)

    assert trajectory() == trajectory()


def test_shipped_schema_is_current() -> None:
    assert SCHEMA_FILE.read_text(encoding="utf-8") == schema_text(), "run: pare scenarios schema -o " + str(
        SCHEMA_FILE
    )


def test_library_coverage() -> None:
    scenarios = list(library().values())
    assert len(scenarios) >= 24
    apps = Counter(
        app for s in scenarios for app in set(s.all_apps) | ({"files"} if "files" in s.seed else set())
    )
    assert set(phone_apps()) <= set(apps), f"apps without a scenario: {set(phone_apps()) - set(apps)}"
    tags = Counter(tag for s in scenarios for tag in s.tags)
    assert all(tags[tag] >= 4 for tag in TAGS), tags
    assert {s.difficulty for s in scenarios} == {"easy", "medium", "hard"}
    mean_apps = sum(len(s.apps) for s in scenarios) / len(scenarios)
    assert 2.0 <= mean_apps <= 3.0, mean_apps
    reactive = [
        s.id for s in scenarios if any(e.when is not None and e.when.actor == "assistant" for e in s.events)
    ]
    assert len(reactive) >= 4, reactive
    report = coverage(scenarios)
    assert report.judge_share >= JUDGE_SHARE_MINIMUM, (report.judged_text_goals, report.text_goals)


def test_no_two_scenarios_tell_the_same_story() -> None:
    most_alike = similarities(list(library().values()))[0]
    assert most_alike.score < THRESHOLD, most_alike


def test_splits() -> None:
    named = splits()
    assert sorted(named["full"]) == sorted(library())
    assert 1 <= len(named["smoke"]) <= 5 and set(named["smoke"]) <= set(named["full"])
    assert (BENCH_DIR / "splits.yaml").exists()
