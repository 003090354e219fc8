"""The scenario's timeline whatever the user does: the clock does not wait on an idle user, and the world's
replies set in motion before the end arrive, after the last turn, before the checks run."""

from __future__ import annotations

import json
from datetime import timedelta
from typing import Any

from pare.bench import EpisodeSettings, run_episode
from pare.bench.selftest import check_scenario
from pare.env import EnvConfig
from pare.scenarios import OracleAssistant, OracleUser, Scenario
from pare.scenarios.oracle import BusyUser
from tests.scenarios.helpers import THANKS, base, parse, replying, sound


def play(scenario: Scenario, settings: EpisodeSettings, *, busy: bool = False) -> Any:
    user = BusyUser(scenario) if busy else OracleUser(scenario)
    return run_episode(scenario, user, OracleAssistant(scenario), settings)


# The oracle: turn 1 both wait (the clock jumps to Ann's email at +5m), turn 2 the user opens Email,
# turn 3 opens Ann's email and the assistant proposes, turn 4 the user accepts and the assistant replies.
LAST_TURN_REPLIES = EpisodeSettings(max_turns=4)


def test_a_reply_due_after_the_last_turn_is_delivered_and_the_check_sees_it() -> None:
    scenario = parse(replying())
    result = play(scenario, LAST_TURN_REPLIES)
    assert result.turns == 4 and result.ended == "max_turns"
    assert result.success
    log = result.env.log.entries
    reply = next(e for e in log if e.tool == "reply_to_email")
    thanks = next(e for e in log if e.event_id == "ann_thanks")
    ps = next(e for e in log if e.event_id == "ann_ps")
    assert thanks.time == reply.time + timedelta(minutes=20)
    assert ps.time == thanks.time + timedelta(minutes=5)  # a reply chained on a reply comes too
    assert "e_thanks" in result.env.snapshot()["email"]["emails"]  # the final state has it
    assert any(op["path"] == "/email/emails/e_thanks" for op in result.state_diff)


def test_only_the_replies_arrive_after_the_last_turn() -> None:
    scenario = parse(replying())
    result = play(scenario, LAST_TURN_REPLIES)
    fired = result.env.scheduler.completed
    assert "newsletter" not in fired  # the story's own next event is not played out after the end
    assert not any(e.event_id and e.event_id.startswith("noise-") for e in result.env.log.entries)
    assert [e.event_id for e in result.env.log.entries if e.turn == 5] == ["ann_thanks", "ann_ps"]


def test_the_trajectory_records_what_arrived_after_the_last_turn() -> None:
    scenario = parse(replying())
    result = play(scenario, LAST_TURN_REPLIES)
    after = result.to_dict()["after_last_turn"]
    reply = next(e for e in result.env.log.entries if e.tool == "reply_to_email")
    assert after == {
        "turn": 5,
        "from": reply.time.isoformat(),
        "until": (reply.time + timedelta(days=1)).isoformat(),
        "delivered": ["ann_thanks", "ann_ps"],
        "beyond": [],
    }
    assert not [step for step in result.steps if step.turn == 5]  # no actor acts after the last turn


def test_no_after_last_turn_record_when_nothing_was_set_in_motion() -> None:
    scenario = parse(base())
    result = play(scenario, EpisodeSettings())
    assert result.after_last_turn is None and result.to_dict()["after_last_turn"] is None


def test_the_horizon_bounds_what_arrives_after_the_last_turn() -> None:
    scenario = parse(replying())
    short = LAST_TURN_REPLIES.model_copy(update={"reaction_horizon": timedelta(minutes=19)})
    result = play(scenario, short)
    assert not result.success  # the thanks comes after the horizon: the check does not see it
    assert result.after_last_turn is not None
    assert result.after_last_turn.delivered == () and result.after_last_turn.beyond == ("ann_thanks",)
    assert "ann_thanks" not in result.env.scheduler.completed

    exact = LAST_TURN_REPLIES.model_copy(update={"reaction_horizon": timedelta(minutes=20)})
    result = play(scenario, exact)
    assert result.success  # due exactly at the horizon: delivered; the chained note 5 minutes later is not
    assert result.after_last_turn is not None
    assert result.after_last_turn.delivered == ("ann_thanks",)
    assert result.after_last_turn.beyond == ("ann_ps",)


def later_story(hours: int = 2) -> Scenario:
    """The base scenario with Ann's email ``hours`` after the start."""
    data = base()
    data["events"][0]["at"] = f"+{hours}h"
    return parse(data)


def test_a_user_who_never_waits_still_sees_the_timeline() -> None:
    scenario = later_story()
    result = play(scenario, EpisodeSettings(), busy=True)
    assert result.success
    user_tools = [s.action.tool for s in result.steps if s.actor == "user"]
    assert "wait" not in user_tools
    arrival = next(e for e in result.env.log.entries if e.event_id == "ann_asks")
    # three turns at a minute each (attention_turns), a fourth, then the clock goes on to Ann's email
    assert arrival.turn == 5 and arrival.time == scenario.start + timedelta(hours=2)


def test_attention_turns_sets_how_long_the_clock_holds_for_a_busy_user() -> None:
    scenario = later_story()
    result = play(scenario, EpisodeSettings(attention_turns=1), busy=True)
    arrival = next(e for e in result.env.log.entries if e.event_id == "ann_asks")
    assert arrival.turn == 3 and result.success


def test_a_busy_user_reading_what_just_arrived_is_not_hurried_past_the_next_event() -> None:
    data = base()
    data["events"].append(
        {
            "id": "later",
            "at": "+3h",
            "tool": "email__receive_email",
            "args": {**THANKS, "email_id": "e_later", "content": "Later."},
        }
    )
    scenario = parse(data)
    result = play(scenario, EpisodeSettings(), busy=True)
    assert result.success
    log = result.env.log.entries
    arrival = next(e for e in log if e.event_id == "ann_asks")
    reply = next(e for e in log if e.tool == "reply_to_email")
    # Ann's email arrives; the user opens it, the assistant proposes, the user accepts: a minute a turn
    assert reply.time - arrival.time == timedelta(minutes=2)
    later = next(e for e in log if e.event_id == "later")
    assert later.turn > reply.turn


def test_a_jump_past_a_busy_user_brings_only_a_turns_worth_of_noise() -> None:
    scenario = later_story(hours=48)
    settings = EpisodeSettings(env=EnvConfig(seed=3, noise_rate_per_minute=2.0))
    result = play(scenario, settings, busy=True)
    assert result.success
    noise = [e for e in result.env.log.entries if e.event_id and e.event_id.startswith("noise-")]
    assert len(noise) < 10 * result.turns  # not the ~5,760 two days would bring


def test_same_seed_same_trajectory_with_a_busy_user_and_replies_after_the_end() -> None:
    scenario = parse(replying())
    # the busy user: four turns before the clock goes on to Ann's email, then three to reply, at the last
    settings = EpisodeSettings(max_turns=7, env=EnvConfig(seed=11, noise_rate_per_minute=1.0))

    def trajectory() -> str:
        return json.dumps(play(scenario, settings, busy=True).to_dict(), sort_keys=True)

    first = trajectory()
    assert json.loads(first)["after_last_turn"]["delivered"] == ["ann_thanks", "ann_ps"]
    assert first == trajectory()


def test_the_gate_demands_the_busy_users_replies_arrive() -> None:
    verdict = check_scenario(parse(sound()))
    busy = verdict.run("busy_user")
    assert busy.ok and busy.expected_success

    # The busy user replies at the last of 8 turns: Ann's answer comes after it, before the checks; but
    # not when she answers two days later, past the horizon (the oracle user waits after the reply, so
    # the clock jumps to her answer).
    settings = EpisodeSettings(max_turns=8)
    verdict = check_scenario(parse(sound()), settings, runs=("busy_user",), variants=False)
    assert verdict.ok and verdict.run("busy_user").after_last_turn == ("ann_confirms",)
    data = sound()
    data["events"][1]["delay"] = "2d"
    verdict = check_scenario(parse(data), settings, runs=("oracle", "busy_user"), variants=False)
    assert verdict.run("oracle").ok and verdict.run("busy_user").success
    assert verdict.breaches() == [
        "tiny_reply [busy_user]: reactive event 'ann_confirms' was set off in the busy_user run but never "
        "delivered"
    ]
