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
    assert problem.splitlines()[0].endswith("(2 places)")


def test_a_loader_problem_quotes_its_line_instead_of_numbering_the_joined_file() -> None:
    data = base()
    data["seed"]["email"]["emails"][0]["subjct"] = "Typo"
    sections = split_sections(to_yaml(data), ORDER).sections
    _, [problem] = load_partial(sections, "seed")
    assert "candidate.yaml" not in problem
    assert "subjct" in problem.splitlines()[0]
    assert "the `seed` section" in problem
    [marked] = [line for line in problem.splitlines() if line.lstrip().startswith(">")]
    assert "subjct: Typo" in marked
    assert (
        len([line for line in problem.splitlines() if " | " in line]) == 3
    )  # the line and a neighbour each side


def test_a_yaml_error_found_after_the_faulty_section_says_something_above_is_left_open() -> None:
    sections = split_sections(to_yaml(base()), ORDER).sections
    sections["user"] = "user: {persona: Busy parent, goal: [unclosed\n"
    story = {key: text for key, text in sections.items() if key in STAGE_KEYS["story"]}
    _, [problem] = load_partial(story, "story")
    assert "not valid YAML" in problem
    assert "stand-in for `oracle`" in problem and "left open" in problem
    _, [problem] = load_partial(sections, "seed")
    assert "where `seed` starts: something above it is left open" in problem
    assert "goal: [unclosed" in problem
