"""Each goal's checks said as sentences, for people reviewing a scenario."""

from __future__ import annotations

from pare.scenarios.checks import check_sentences
from pare.scenarios.loader import parse_scenario
from tests.scenarios.helpers import base, to_yaml


def test_every_check_of_every_goal_is_said_in_order_with_its_own_description_first() -> None:
    data = base()
    data["goals"][0]["checks"] += [
        {"no_action": {"tool": "email__delete_email"}, "description": "Nothing deleted."},
        {"state": {"path": "email.user_email", "value": {"contains": "pare"}}},
    ]
    sentences = check_sentences(parse_scenario(to_yaml(data)))
    [first, deleted, state] = sentences["replied"]
    assert "email__reply_to_email" in first and "thursday" in first
    assert deleted.startswith("Nothing deleted: no ") and "email__delete_email" in deleted
    assert state.startswith("email.user_email matches") and "pare" in state
