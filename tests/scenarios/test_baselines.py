"""The model-free assistants against the whole library with the oracle user: a floor that no assistant
doing nothing useful may rise above. A silent assistant succeeding beyond the no-proposal share means a
scenario passes without the task being done: a defect of the library."""

from __future__ import annotations

import pytest

from pare.bench import EpisodeSettings, run_episode
from pare.env import EnvConfig
from pare.scenarios.baselines import BASELINES, GENERIC_OFFER
from pare.scenarios.library import library
from pare.scenarios.model import Scenario
from pare.scenarios.oracle import OracleUser

_PLAYED: dict[str, dict[str, bool]] = {}


def _successes(name: str, scenarios: list[Scenario]) -> dict[str, bool]:
    if name in _PLAYED:
        return _PLAYED[name]
    results = _PLAYED[name] = {}
    for scenario in scenarios:
        assistant = BASELINES[name].build(scenario, 7)
        result = run_episode(
            scenario, OracleUser(scenario), assistant, EpisodeSettings(env=EnvConfig(seed=7))
        )
        results[scenario.id] = result.outcome.success
    return results


@pytest.fixture(scope="module")
def scenarios() -> list[Scenario]:
    return sorted(library().values(), key=lambda s: s.id)


@pytest.mark.parametrize("name", sorted(BASELINES))
def test_no_baseline_succeeds_where_a_task_was_needed(name: str, scenarios: list[Scenario]) -> None:
    won = _successes(name, scenarios)
    needed_a_task = sorted(sid for sid, ok in won.items() if ok and library()[sid].kind == "proposal")
    assert needed_a_task == [], f"{name} passes scenarios whose task it never did"
    no_proposal_share = sum(s.kind == "no_proposal" for s in scenarios) / len(scenarios)
    assert sum(won.values()) / len(scenarios) <= no_proposal_share


def test_silent_succeeds_exactly_on_the_no_proposal_scenarios(scenarios: list[Scenario]) -> None:
    won = _successes("silent", scenarios)
    assert {sid for sid, ok in won.items() if ok} == {s.id for s in scenarios if s.kind == "no_proposal"}


def test_baselines_are_deterministic_and_do_what_they_say() -> None:
    scenario = library()["partner_already_ordered_batteries_needs_nothing"]
    proposal_scenario = next(
        s for s in sorted(library().values(), key=lambda s: s.id) if s.kind == "proposal"
    )
    settings = EpisodeSettings(env=EnvConfig(seed=3))
    first = run_episode(
        proposal_scenario,
        OracleUser(proposal_scenario),
        BASELINES["random"].build(proposal_scenario, 3),
        settings,
    )
    second = run_episode(
        proposal_scenario,
        OracleUser(proposal_scenario),
        BASELINES["random"].build(proposal_scenario, 3),
        settings,
    )
    assert first.to_dict() == second.to_dict()
    offered = run_episode(
        scenario, OracleUser(scenario), BASELINES["generic_offer"].build(scenario, 3), settings
    )
    proposals = [e for e in offered.env.log if e.tool == "send_message_to_user" and e.mode == "observe"]
    assert proposals and all(e.args["content"] == GENERIC_OFFER for e in proposals)
    only = run_episode(
        proposal_scenario,
        OracleUser(proposal_scenario),
        BASELINES["propose_only"].build(proposal_scenario, 3),
        settings,
    )
    writes = [e for e in only.env.log if e.actor == "assistant" and e.kind == "write" and e.app != "agent_ui"]
    assert writes == []
    assert any(e.actor == "user" and e.tool == "accept_proposal" for e in only.env.log)
