"""Protocol presets: one declaration of the protocol, the two presets and where they differ, overrides on
top of a preset, the identity of runs made before presets, and what the paper's protocol plays like.
"""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any

import pytest

from pare.agents.actions import format_action
from pare.agents.llm import LLMAssistant, LLMUser
from pare.agents.prompts import observe_system_prompt, user_system_prompt
from pare.agents.scripted import ScriptedModel
from pare.bench import EpisodeSettings, run_episode
from pare.bench.runconfig import RunConfig, WorldSettings, build_config
from pare.env import EnvConfig, Environment
from pare.errors import UserInputError
from pare.protocols import PRESETS, ProtocolSettings, manifest_protocol, preset_differences
from pare.sim.budget import DEFAULT_BUDGET, TurnBudget
from tests.agents.test_scripted_actors import WAIT_ASSISTANT, WAIT_USER
from tests.scenarios.helpers import base, parse

CONFORMANCE = Path(__file__).parents[2] / "docs" / "paper-conformance.md"
SCENARIO = parse(base())  # Ann's email arrives 5 minutes in; the goal is a reply that says Thursday


def _documented_preset_table() -> dict[str, tuple[Any, Any]]:
    """The rows of the conformance page's table of what ``--protocol paper`` changes."""
    text = CONFORMANCE.read_text(encoding="utf-8")
    section = text.split("## What `--protocol paper` changes", 1)[1].split("\n## ", 1)[0]
    rows = re.findall(r"^\| `protocol\.(\w+)` \| `([^`]*)` \| `([^`]*)` \|$", section, re.MULTILINE)
    return {name: (_json_value(pare), _json_value(paper)) for name, pare, paper in rows}


def _json_value(text: str) -> Any:
    if text == "null":
        return None
    return int(text) if text.isdigit() else text


def test_the_presets_differ_exactly_where_the_conformance_page_says() -> None:
    documented = _documented_preset_table()
    assert documented  # the table is there and was read
    assert preset_differences("pare", "paper") == documented
    assert set(PRESETS) == {"pare", "paper"}


def test_the_pare_preset_is_the_declared_default_everywhere() -> None:
    # one declaration: the episode's settings, the actors' budget and a run's protocol start from it
    declared = TurnBudget().model_dump()
    assert EpisodeSettings().budget().model_dump() == declared == DEFAULT_BUDGET.model_dump()
    pare = ProtocolSettings()
    assert pare.budget().model_dump() == declared and pare.preset == "pare" and pare.overrides() == {}
    assert RunConfig().episode_settings(7).model_dump() == EpisodeSettings(env=EnvConfig(seed=7)).model_dump()
    assert {*TurnBudget.model_fields} < {*EpisodeSettings.model_fields} and {*TurnBudget.model_fields} < {
        *ProtocolSettings.model_fields
    }
    # the world: a run's world settings are a part of an episode's world, declared once
    assert {*WorldSettings.model_fields} < {*EnvConfig.model_fields}


def test_every_protocol_setting_reaches_the_episode() -> None:
    config = build_config(
        {
            "protocol": {
                "preset": "paper",
                "max_turns": 12,
                "user_steps": 2,
                "observe_steps": 3,
                "execute_steps": 7,
                "turn_duration": "2m",
                "attention_turns": 5,
                "reaction_horizon": "3h",
            },
            "world": {"tool_failure_probability": 0.25, "noise_rate_per_minute": 1.5},
        }
    )
    settings = config.episode_settings(42)
    assert settings.budget().model_dump() == config.protocol.budget().model_dump()
    assert (settings.max_turns, settings.user_steps, settings.observe_steps, settings.execute_steps) == (
        12,
        2,
        3,
        7,
    )
    assert settings.turn_minutes == 2 and settings.attention_turns == 5
    assert settings.reaction_horizon.total_seconds() == 3 * 3600
    assert settings.proposal_ttl_turns is None and settings.user_prompt == "paper"  # from the preset
    assert settings.env.seed == 42 and settings.env.tool_failure_probability == 0.25
    assert settings.env.noise_rate_per_minute == 1.5


def test_settings_given_beside_a_preset_override_it_and_are_recorded() -> None:
    config = build_config({"protocol": {"preset": "paper", "max_turns": 20, "proposal_ttl_turns": 4}})
    protocol = config.protocol
    assert protocol.max_turns == 20 and protocol.proposal_ttl_turns == 4
    assert protocol.user_prompt == "paper" and protocol.max_format_retries == 0  # the rest is the paper's
    record = protocol.record()
    assert record["preset"] == "paper"
    assert record["overrides"] == {"max_turns": 20, "proposal_ttl_turns": 4}
    # a flag overrides the file's preset, and the file's settings stay overrides of the new one
    flagged = build_config(
        {"protocol": {"preset": "paper", "max_turns": 20}}, overrides=[("protocol.preset", "pare")]
    )
    assert flagged.protocol.preset == "pare" and flagged.protocol.overrides() == {"max_turns": 20}


def test_an_unknown_preset_is_refused_with_the_presets_named() -> None:
    with pytest.raises(UserInputError, match=r"protocol: .*unknown protocol preset 'papr'.*'paper'"):
        build_config({"protocol": {"preset": "papr"}})


def test_runs_made_before_presets_keep_their_identity() -> None:
    # hashes of configurations written before presets existed: their folders must still resume
    assert build_config({}).identity_hash() == "0aeacae53e"
    older = {
        "models": {"assistant": {"model": "gpt-4o"}, "user": {"model": "x"}},
        "protocol": {"max_turns": 20, "turn_duration": "2m"},
    }
    assert build_config(older).identity_hash() == "aeb6df43e0"
    assert build_config({"world": {"noise_rate_per_minute": 2}}).identity_hash() == "ddf23ac044"


def test_the_preset_and_new_settings_enter_the_identity_when_they_change_anything() -> None:
    pare, paper = build_config({}), build_config({"protocol": {"preset": "paper"}})
    assert pare.identity_hash() != paper.identity_hash()
    assert paper.identity()["protocol"]["preset"] == "paper"
    assert "preset" not in pare.identity()["protocol"]
    horizon = build_config({"protocol": {"reaction_horizon": "1h"}})
    assert horizon.identity_hash() != pare.identity_hash()


def test_a_manifest_written_before_presets_reads_as_the_pare_protocol_with_its_overrides() -> None:
    old = {"config": {"protocol": {"max_turns": 20, "proposal_ttl_turns": 4, "turn_duration": "PT1M"}}}
    assert manifest_protocol(old) == ("pare", {"max_turns": 20})
    assert manifest_protocol({}) == ("pare", {})
    recorded = {
        "protocol": build_config({"protocol": {"preset": "paper", "max_turns": 12}}).protocol.record()
    }
    assert manifest_protocol(recorded) == ("paper", {"max_turns": 12})


# -- what the paper's protocol tells the models and plays like -------------------------------------------
def test_the_paper_user_prompt_is_the_appendix_wording_and_ours_is_not() -> None:
    env = Environment(["email"])
    paper = " ".join(user_system_prompt(env, budget=ProtocolSettings(preset="paper").budget()).split())
    ours = " ".join(user_system_prompt(env, budget=ProtocolSettings().budget()).split())
    strict = "You have to be EXTREMELY STRICT about accepting proposals."
    assert paper.count(strict) == 2
    assert "If you are not sure, simply reject the proposal." in paper
    assert "Be a demanding user" not in paper and "check the one thing you need first" not in paper
    assert "withdrawn" not in paper  # the paper's proposals never expire
    assert strict not in ours and "Be a demanding user" in ours and "withdrawn" in ours
    # the wording is a setting of its own: PARE's protocol can take the paper's words
    words_only = user_system_prompt(env, budget=TurnBudget(user_prompt="paper"))
    assert strict in words_only and "A proposal waits 4 turns for your answer" in " ".join(words_only.split())


def test_without_expiry_the_prompts_say_a_proposal_waits_to_the_end() -> None:
    env = Environment(["email"])
    budget = TurnBudget(proposal_ttl_turns=None)
    observe = " ".join(observe_system_prompt(env, budget=budget).split())
    assert "it waits for the user's answer until the session ends" in observe and "withdrawn" not in observe
    user = " ".join(user_system_prompt(env, budget=budget).split())
    assert "A proposal waits for your answer until the session ends." in user and "withdrawn" not in user


def _say(tool: str, args: dict[str, Any] | None = None) -> str:
    return format_action(tool, args or {}, "Next step.")


def test_without_expiry_an_unanswered_proposal_is_never_withdrawn() -> None:
    never_answers = [_say("wait"), _say("open_app", {"app_name": "email"}), *[_say("wait")] * 8]
    proposes = [
        WAIT_ASSISTANT,
        _say("email__get_email_by_id", {"email_id": "e_ann"}),
        _say("agent_ui__send_message_to_user", {"content": "Reply to Ann that Thursday works for you."}),
    ]
    user = LLMUser(ScriptedModel(never_answers, fallback=WAIT_USER))
    assistant = LLMAssistant(ScriptedModel(proposes, fallback=WAIT_ASSISTANT))
    result = run_episode(SCENARIO, user, assistant, EpisodeSettings(max_turns=8, proposal_ttl_turns=None))
    assert result.expired_proposals == [] and result.expired_at == {}
    views = [step.view for step in result.steps if step.view is not None]
    later = views[2:]
    assert later and all(view["pending_proposal"] for view in later)  # still pending at the end
    assert all("proposal_turns_left" not in view for view in views)
    assert result.turns == 8  # a pending proposal keeps the episode going to its limit
    told = [m.content or "" for m in user.conversation.messages if m.role == "user"]
    assert all("withdrawn" not in text and "withdrew" not in text for text in told)


def test_the_paper_preset_counts_a_malformed_answer_as_a_step() -> None:
    # PARE sends it back within the step; the paper's budgets count every answer, so it costs the step
    malformed, wait = "I think I will open the email app.", _say("wait")
    outcomes = {}
    for preset in ("pare", "paper"):
        retries = ProtocolSettings.model_validate({"preset": preset}).max_format_retries
        model = ScriptedModel([malformed, wait], fallback=WAIT_USER)
        assistant = LLMAssistant(ScriptedModel([], fallback=WAIT_ASSISTANT))
        result = run_episode(
            SCENARIO, LLMUser(model, max_format_retries=retries), assistant, EpisodeSettings(max_turns=1)
        )
        first = result.steps[0]
        outcomes[preset] = (len(model.requests), first.ok, first.action.tool)
    assert outcomes == {"pare": (2, True, "wait"), "paper": (1, False, "")}
