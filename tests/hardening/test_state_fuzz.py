"""Fuzzing the environment: after every call that succeeds, every app's state is still valid.

Error results changing nothing is tested elsewhere; this walks seeded random users and assistants through
library scenarios (every app, real seed data) and re-validates each app's whole state after each
successful call, so a write that leaves records contradicting their own rules (an order updated before it
was placed, a note attached twice, a ride under way that is not the current one) is caught where it
happens.
"""

from __future__ import annotations

import json
import random
from datetime import timedelta

import pytest

from pare.env import Environment
from pare.env.random_walk import RandomAssistant, RandomUser
from pare.scenarios.build import build_environment
from pare.scenarios.library import load_scenarios

SCENARIOS = (
    "dentist_moves_checkup",  # email, calendar
    "flatmate_away_restock_order",  # shopping, messaging
    "shared_cab_to_birthday_dinner_driver_cancels",  # cab
    "partner_rent_ceiling_prunes_saved_flats",  # apartment
    "climbing_session_clash_find_tuesday",  # reminder
    "dinner_guest_nut_allergy_menu_note",  # notes
    "flat_chat_signed_lease_save_a_copy",  # files, messaging
    "tutor_details_shared_in_class_chat_save_contact",  # contacts
    "rent_rises_replace_standing_order_from_first",  # banking (standing orders paid as time passes), email
    "unrecognised_card_payment_freeze_and_dispute",  # banking (cards, disputes)
)
STEPS = 300


def assert_every_app_valid(env: Environment, after: str) -> None:
    for name, app in env.apps.items():
        snapshot = app.snapshot()
        json.dumps(snapshot, allow_nan=False)
        try:
            type(app.state).model_validate(snapshot)
        except ValueError as error:  # pydantic's ValidationError is a ValueError
            raise AssertionError(f"app '{name}' holds invalid state after {after}: {error}") from None


@pytest.mark.parametrize("scenario_id", SCENARIOS)
def test_state_stays_valid_through_a_random_walk(scenario_id: str) -> None:
    scenario = next(s for s in load_scenarios() if s.id == scenario_id)
    for seed in (1, 2):
        env = build_environment(scenario)
        rng = random.Random(seed)
        user, assistant = RandomUser(rng), RandomAssistant(rng)
        for step in range(STEPS):
            actor = user if rng.random() < 0.5 else assistant
            result = actor.step(env)
            if result.ok:
                entry = result.entry
                where = f"step {step}" + (
                    f" ({entry.actor} {entry.app}.{entry.tool} {entry.args})" if entry else ""
                )
                assert_every_app_valid(env, where)
            if rng.random() < 0.1:
                env.advance(timedelta(minutes=rng.choice([1, 5, 30])))


@pytest.mark.parametrize("scenario_id", SCENARIOS)
def test_a_write_changes_only_its_app_and_the_apps_it_declares(scenario_id: str) -> None:
    """Attribution diffs only the written app and its ``also_writes`` around a write: a tool that changes
    any other app's data would go unattributed, so none may."""
    scenario = next(s for s in load_scenarios() if s.id == scenario_id)
    env = build_environment(scenario)
    rng = random.Random(7)
    user, assistant = RandomUser(rng), RandomAssistant(rng)
    for step in range(150):
        before = env.snapshot()
        result = (user if rng.random() < 0.5 else assistant).step(env)
        entry = result.entry
        if not result.ok or entry is None or entry.kind != "write" or entry.app not in env.apps:
            continue
        after = env.snapshot()
        allowed = {entry.app, *env.apps[entry.app].also_writes}
        changed = {name for name in after if after[name] != before.get(name)}
        assert changed <= allowed, (
            f"step {step}: {entry.app}.{entry.tool} changed {sorted(changed - allowed)}"
        )
