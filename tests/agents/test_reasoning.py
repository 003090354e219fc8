"""Thinking models: reasoning, inline or beside the answer, is kept apart and never read as the action."""

from __future__ import annotations

import pytest

from pare.agents.actions import FORMAT_HINT, format_action, parse_action
from pare.agents.models.reasoning import join_reasoning, split_reasoning
from pare.errors import ActionFormatError

ANSWER = format_action("email__get_email_by_id", {"email_id": "e_ann"}, "Read Ann's email first.")
DRAFT = 'A first idea:\nAction:\n{"action": "system__wait", "action_input": {}}\nNo, better to read first.'


@pytest.mark.parametrize(
    ("text", "answer", "reasoning"),
    [
        ("Thought: x", "Thought: x", None),
        ("<think>\nweigh it\n</think>\n\nThought: x", "Thought: x", "weigh it"),
        ("weigh it, mid-thought\n</think>\n\nThought: x", "Thought: x", "weigh it, mid-thought"),
        ("<think></think>\n\nThought: x", "Thought: x", None),  # thinking switched off
        ("<THINK>a</Think> Thought: x <think>b</think>", "Thought: x", "a\n\nb"),
        ("Thought: x\n<think>cut off while thinking", "Thought: x", "cut off while thinking"),
        ("<think>a <think> b</think>c</think>", "c</think>", "a <think> b"),  # stray tags stay as text
    ],
    ids=["none", "block", "unopened", "empty-block", "several", "unclosed", "stray-tags"],
)
def test_split_reasoning_takes_think_blocks_out_of_the_answer(
    text: str, answer: str, reasoning: str | None
) -> None:
    assert split_reasoning(text) == (answer, reasoning)


def test_join_reasoning_keeps_what_is_said() -> None:
    assert join_reasoning(None, " ", "") is None
    assert join_reasoning(" field ", None, "inline\n") == "field\n\ninline"


def test_an_action_drafted_inside_a_think_block_is_not_read() -> None:
    parsed = parse_action(f"<think>\n{DRAFT}\n</think>\n\n{ANSWER}")
    assert (parsed.tool, parsed.args) == ("email__get_email_by_id", {"email_id": "e_ann"})
    assert parsed.thought == "Read Ann's email first."
    assert parsed.reasoning == DRAFT


def test_a_leading_block_without_its_opening_tag_is_reasoning() -> None:
    # The chat template put <think> in the prompt: the answer starts mid-thought.
    parsed = parse_action(f"{DRAFT}\n</think>\n\n{ANSWER}")
    assert parsed.tool == "email__get_email_by_id"
    assert parsed.reasoning == DRAFT


def test_reasoning_given_beside_the_answer_is_kept_with_the_inline_kind() -> None:
    parsed = parse_action(f"<think>second look</think>{ANSWER}", reasoning=DRAFT)
    assert parsed.tool == "email__get_email_by_id"
    assert parsed.reasoning == f"{DRAFT}\n\nsecond look"
    assert parse_action(ANSWER, reasoning=DRAFT).reasoning == DRAFT


@pytest.mark.parametrize(
    ("text", "reasoning"),
    [
        (f"<think>\n{DRAFT}\n</think>", None),
        (f"{DRAFT}\n</think>\n", None),
        (f"<think>\n{DRAFT}", None),  # cut off while thinking
        ("", DRAFT),  # the reasoning field only
        ("  \n", DRAFT),
    ],
    ids=["block", "unopened", "unclosed", "field", "field-blank-text"],
)
def test_an_answer_that_is_only_thinking_is_told_it_has_no_action(text: str, reasoning: str | None) -> None:
    with pytest.raises(ActionFormatError) as caught:
        parse_action(text, reasoning=reasoning)
    assert caught.value.kind == "no_action"
    message = str(caught.value)
    assert "only your reasoning" in message and "no Action: section" in message
    assert message.endswith(FORMAT_HINT)


def test_an_empty_answer_without_reasoning_is_still_empty() -> None:
    for text in ("", "<think></think>"):
        with pytest.raises(ActionFormatError) as caught:
            parse_action(text)
        assert caught.value.kind == "empty"


def test_the_raw_answer_is_kept_as_written() -> None:
    text = f"<think>{DRAFT}</think>\n{ANSWER}"
    assert parse_action(text).raw == text
