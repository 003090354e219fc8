"""Answers cut into sections, candidates assembled, the judge's verdict read."""

from __future__ import annotations

import pytest

from pare.generate.checking import load_partial
from pare.generate.prompts import STAGE_HEADINGS, TEMPLATES
from pare.generate.sections import ORDER, STAGE_KEYS, STAGES, assemble, extract_yaml, split_sections, top_key
from pare.generate.uniqueness import JudgeAnswerError, read_verdict
from tests.scenarios.helpers import base, to_yaml


def test_the_yaml_of_an_answer_is_its_fenced_blocks_or_the_whole_text() -> None:
    assert extract_yaml("Here it is:\n```yaml\nseed: {}\n```\nDone.") == "seed: {}\n"
    assert extract_yaml("seed: {}\n") == "seed: {}\n"


def test_sections_keep_their_comments_and_refuse_other_stages_keys() -> None:
    split = split_sections("# the data\nseed:\n  email: {}\n# variants next\ngoals: []\n", ["seed"])
    assert split.sections["seed"] == "seed:\n  email: {}\n# variants next\n"
    assert split.problems == (
        "top-level key 'goals' cannot be written here (it belongs to the validation stage); write only: seed",
    )
    twice = split_sections("seed: {}\nseed: {}\n", ["seed"])
    assert "top-level key 'seed' is written twice" in twice.problems
    assert split_sections("Sorry, I cannot.", ["seed"]).problems[0].startswith("text before the first")
    assert "not a field of scenario files" in split_sections("colour: red\n", ["seed"]).problems[0]


def test_a_candidate_is_assembled_in_file_order_with_placeholders_for_what_is_missing() -> None:
    text = assemble({"seed": "seed: {}\n", "id": "id: x\n"}, placeholders=True)
    assert text.index("id: x") < text.index("seed:") < text.index("oracle:") < text.index("goals:")
    assert "no_proposal" not in text and "proposal: Written by a later stage." in text
    quiet = assemble({"kind": "kind: no_proposal\n"}, placeholders=True)
    assert "oracle: {}" in quiet
    assert list(ORDER).index("oracle") < list(ORDER).index("variants")  # anchors come before merges
    assert top_key("seed.email.emails[0]") == "seed" and top_key("") == ""


def test_the_judges_verdict_is_read_from_its_json() -> None:
    assert read_verdict('Verdict: {"duplicate": true, "same_as": "a_b", "reason": "same"}') == (
        True,
        "a_b",
        "same",
    )
    assert read_verdict('{"duplicate": false}') == (False, None, "(no reason given)")
    for text in ("no", "{duplicate: yes}", '{"duplicate": "yes"}'):
        with pytest.raises(JudgeAnswerError):
            read_verdict(text)


def test_the_stage_headings_open_the_stage_templates() -> None:
    for stage, heading in STAGE_HEADINGS.items():
        assert (TEMPLATES / f"{stage}.j2").read_text().startswith(heading)


def test_one_mistake_goes_back_to_the_generator_once_with_its_places() -> None:
    data = base()
    data["oracle"]["user"][1]["args"]["email_id"] = "e_anne"
    data["oracle"]["interventions"][0]["actions"][0]["args"]["email_id"] = "e_anne"
    keys = [key for stage in STAGES for key in STAGE_KEYS[stage]]
    sections = split_sections(to_yaml(data), keys).sections
    scenario, problems = load_partial(sections, STAGES[-1])
    assert scenario is None
    [problem] = problems
    assert "oracle.user[1].args.email_id, oracle.interventions[0].actions[0].args.email_id" in problem
    assert problem.endswith("(2 places)")
