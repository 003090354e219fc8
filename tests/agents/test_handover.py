"""Execute mode starts from what observe mode read: the ids and short facts it saw, bounded in size."""

from __future__ import annotations

from dataclasses import replace
from datetime import datetime
from typing import Any

from pare.agents.actions import format_action
from pare.agents.handover import Handover
from pare.agents.llm import LLMAssistant, LLMUser
from pare.agents.prompts import observe_system_prompt
from pare.agents.scripted import ScriptedModel
from pare.bench import run_episode
from pare.env import Environment
from pare.sim.log import LogEntry, ToolKind
from tests.scenarios.helpers import base, parse

SCENARIO = parse(base())
WAIT_USER = format_action("wait", {}, "Nothing to do.")
WAIT_ASSISTANT = format_action("system__wait", {}, "Nothing to do.")
PROPOSE = format_action("agent_ui__send_message_to_user", {"content": "Reply to Ann that Thursday works."})


def _entry(
    tool: str, result: Any, *, kind: ToolKind = "read", args: dict[str, Any] | None = None
) -> LogEntry:
    return LogEntry(
        index=0,
        turn=1,
        time=datetime(2025, 3, 3, 9),
        actor="assistant",
        app="shop",
        tool=tool,
        args=args or {},
        kind=kind,
        ok=True,
        result=result,
    )


def _play(observe_script: list[str]) -> str:
    """The first message of the execute conversation after observe mode played ``observe_script``."""
    user = LLMUser(
        ScriptedModel(
            [
                WAIT_USER,
                format_action("open_app", {"app_name": "email"}),
                format_action("open_email", {"email_id": "e_ann"}),
                format_action("accept_proposal", {"reason": "yes"}),
            ],
            fallback=WAIT_USER,
        )
    )
    observe = ScriptedModel(observe_script, fallback=WAIT_ASSISTANT)
    execute = ScriptedModel(
        [
            format_action("email__reply_to_email", {"email_id": "e_ann", "content": "Thursday works!"}),
            format_action("agent_ui__send_message_to_user", {"content": "Done."}),
        ]
    )
    result = run_episode(SCENARIO, user, LLMAssistant(observe, execute))
    assert result.success
    first = execute.requests[0]
    assert [message.role for message in first] == ["system", "user"]
    return first[1].content or ""


def test_execute_mode_is_handed_the_email_observe_mode_read() -> None:
    opening = _play(
        [
            WAIT_ASSISTANT,
            WAIT_ASSISTANT,
            format_action("email__get_email_by_id", {"email_id": "e_ann"}),
            PROPOSE,
        ]
    )
    read = next(line for line in opening.splitlines() if line.startswith("- email.get_email_by_id"))
    assert "email_id=e_ann" in read
    assert "Thursday" in read  # a fact of the email (its subject or text), not only its id
    assert opening.rstrip().endswith("Action 1 of 10.")


def test_without_reads_execute_mode_still_gets_the_ids_of_the_users_actions() -> None:
    opening = _play([WAIT_ASSISTANT, WAIT_ASSISTANT, PROPOSE])
    assert "- the user's email.open_email: email_id=e_ann" in opening
    assert "get_email_by_id" not in opening


def test_nested_records_name_the_record_they_are_inside() -> None:
    handover = Handover()
    product = {
        "product_id": "prod-mug",
        "name": "Ceramic Mug",
        "in_stock": [{"item_id": "mug-blue", "name": "Blue", "price": 8.5}],
    }
    handover.read(_entry("search_product", [product]))
    lines = handover.render().splitlines()[1:]
    assert lines[0].startswith("- shop.search_product: product_id=prod-mug, name=Ceramic Mug")
    assert "item_id=mug-blue, name=Blue, price=8.5 (in prod-mug Ceramic Mug)" in lines[1]


def test_writes_and_failures_are_not_handed_over() -> None:
    handover = Handover()
    handover.read(_entry("add_to_cart", {"item_id": "mug-blue"}, kind="write"))
    handover.read(replace(_entry("get_item", {"item_id": "mug-red"}), ok=False, error="sold out"))
    assert handover.render() == ""


def test_the_handover_keeps_the_newest_items_and_cuts_long_lines() -> None:
    handover = Handover(max_items=3, max_line=80)
    handover.read(_entry("list", [{"id": f"n{i}", "text": "word " * 40} for i in range(10)]))
    handover.read(_entry("get", {"id": "n8", "title": "seen again"}))
    lines = handover.render().splitlines()[1:]
    assert [line.split("id=")[1].split(",")[0] for line in lines] == ["n7", "n9", "n8"]
    assert "seen again" in lines[-1]
    assert all(len(line) <= 2 + 80 for line in lines)


def test_the_observe_prompt_says_the_executor_sees_the_proposal_and_the_ids_only() -> None:
    prompt = " ".join(observe_system_prompt(Environment(["email", "contacts"])).split())
    assert "it sees your proposal, the user's answer, and the items you read with their ids" in prompt
    assert "not this conversation" in prompt
