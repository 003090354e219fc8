"""What actors are shown: tool results as text."""

from __future__ import annotations

from pare.env import ToolResult


def test_an_observation_is_written_once_and_is_not_part_of_the_result_s_identity() -> None:
    result = ToolResult(ok=True, value={"emails": ["e1"]}, screen_display={"folder": "INBOX"})
    text = result.observation()
    assert text == '{"emails": ["e1"]}\nOn screen: {"folder": "INBOX"}'
    assert result.observation() is text  # the loop records it and the actor is shown it: written once
    assert result == ToolResult(ok=True, value={"emails": ["e1"]}, screen_display={"folder": "INBOX"})
    assert "_observation" not in repr(result)
    assert ToolResult(ok=False, error="No such email.").observation() == "Error: No such email."
