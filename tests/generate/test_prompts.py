"""What the generator's prompts tell the model, and that each long section is said once."""

from __future__ import annotations

import json

from pare.generate.context import REFERENCE_KEY, apps_reference, describe_once, schema_text
from pare.generate.prompts import stage_prompt, system_prompt
from pare.generate.sections import STAGE_KEYS
from pare.scenarios.schema import scenario_json_schema
from pare.scenarios.seed_format import seed_format

MATCHER_OPENING = "A value (equal to it), a mapping of operators"


def test_the_matcher_description_is_said_once_per_conversation() -> None:
    assert json.dumps(scenario_json_schema()).count(MATCHER_OPENING) > 1  # the shipped schema repeats it
    system = system_prompt(None)
    assert system.count(MATCHER_OPENING) == 1
    assert "Same as the description of ActionCheck.args." in system
    for stage in ("seed", "events", "validation"):
        message = stage_prompt(stage, apps=["email", "calendar"], candidate="id: x\n")
        assert MATCHER_OPENING not in message
        assert message.count(REFERENCE_KEY) <= 1


def test_the_compact_schema_keeps_every_field_and_says_where_a_repeated_description_is() -> None:
    schema = {
        "$defs": {
            "A": {"title": "A", "properties": {"x": {"title": "X", "description": "long " * 40}}},
            "B": {"properties": {"y": {"description": "long " * 40}, "z": {"description": "short"}}},
        }
    }
    compact = describe_once(schema)
    assert compact["$defs"]["A"] == {"properties": {"x": {"description": "long " * 40}}}
    assert compact["$defs"]["B"]["properties"]["y"] == {"description": "Same as the description of A.x."}
    assert compact["$defs"]["B"]["properties"]["z"] == {"description": "short"}
    full = scenario_json_schema()
    assert set(json.loads(schema_text())["$defs"]) == set(full["$defs"])


def test_the_story_stage_names_every_key_it_may_write_and_only_those() -> None:
    prompt = stage_prompt("story", apps=["email"], candidate="", tag="goal_inference")
    for key in STAGE_KEYS["story"]:
        assert f"`{key}`" in prompt, key
    assert "`end_when_met` (`true` ends the episode once every goal is met" in prompt
    assert "and no others" in prompt


def test_the_rules_say_how_text_and_conditions_are_read() -> None:
    system = " ".join(system_prompt(None).split())
    assert "as of when the text was sent, not the scenario's start" in system
    assert '"no", "not"' in system
    assert "`present: false` matches an argument that is missing" in system
    assert "both `event` and `action` holds only once both have happened" in system


def test_a_seed_field_filled_in_when_left_out_is_not_called_required() -> None:
    [set_for] = [line for line in seed_format("reminder") if line.strip().startswith("set_for:")]
    assert "required" not in set_for and "the due time when left out" in set_for
    [due] = [line for line in seed_format("reminder") if line.strip().startswith("due_datetime:")]
    assert "required" in due


def test_the_references_explain_their_notation_once() -> None:
    text = apps_reference(["email", "calendar", "messaging"], seed=False, tools=True)
    assert text.count(REFERENCE_KEY) == 1 and text.count("Agent tools:") >= 3
