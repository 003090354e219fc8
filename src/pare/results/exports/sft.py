"""The successful episodes' conversations per role as chat-format JSON lines, for fine-tuning.

The trajectory keeps what each model *wrote* (every step's raw answer, and a thinking model's reasoning
apart) and what came back (the observation), and for the user the phone as it saw it; it does not keep
the prompts as sent (the system prompt, and the text of each turn's observation as rendered for the
model). Each conversation is therefore rebuilt: a ``user`` message per step with what the step's input
is known to be (the last observation, and for the user the phone), then the model's own answer as the
``assistant`` message, verbatim. One conversation per role of an episode: ``user``, ``observe``, and one
``execute`` conversation per task carried out (a run of consecutive execute steps). Steps no model wrote
(the oracle's, a scripted policy's) give no conversation.
"""

from __future__ import annotations

import json
from collections.abc import Iterator, Sequence
from pathlib import Path
from typing import Any

from pare.errors import UserInputError
from pare.results.exports.episodes import Episode, complete_episodes
from pare.results.records import role_of
from pare.results.run_folder import LoadedRun
from pare.results.trajectory import StepRecord, ViewRecord

ROLES = ("user", "observe", "execute")


def export_sft(
    runs: Sequence[LoadedRun], out: Path, *, roles: Sequence[str] = ROLES, include_failed: bool = False
) -> int:
    """Write the conversations of the successful episodes of ``runs`` (every complete one with
    ``include_failed``) to the JSON-lines file ``out``, replacing it; return how many lines were written.

    Raises:
        UserInputError: An unknown role, a trajectory that cannot be read, or a write refused.
    """
    unknown = [role for role in roles if role not in ROLES]
    if unknown:
        raise UserInputError(f"--role {unknown[0]!r}: choose among {', '.join(ROLES)}")
    lines = [
        json.dumps(conversation, ensure_ascii=False)
        for run in runs
        for episode in complete_episodes(run)
        if include_failed or episode.record.success
        for conversation in conversations(episode, run.label)
        if conversation["role"] in roles
    ]
    try:
        out.write_text("".join(line + "\n" for line in lines), encoding="utf-8")
    except OSError as error:
        raise UserInputError(f"{out}: cannot write the conversations: {error.strerror or error}") from None
    return len(lines)


def conversations(episode: Episode, label: str) -> Iterator[dict[str, Any]]:
    """The episode's conversations, one per role (per task for ``execute``), in the order they began."""
    groups: list[tuple[str, list[StepRecord]]] = []
    open_groups: dict[str, list[StepRecord]] = {}
    previous_role: str | None = None
    for step in episode.trajectory.steps:
        role = role_of(step.actor, step.mode)
        if role == "execute" and previous_role != "execute":
            open_groups.pop("execute", None)  # a new task starts a new conversation
        if role not in open_groups:
            open_groups[role] = []
            groups.append((role, open_groups[role]))
        open_groups[role].append(step)
        previous_role = role
    record = episode.record
    for task, (role, steps) in enumerate(groups):
        if not steps or any(step.action.raw is None for step in steps):
            continue  # not written by a model
        yield {
            "messages": _messages(steps),
            "role": role,
            "scenario_id": record.scenario_id,
            "run": record.run,
            "success": record.success,
            "configuration": label,
            "conversation": task,
        }


def _messages(steps: list[StepRecord]) -> list[dict[str, str]]:
    messages: list[dict[str, str]] = []
    last: str | None = None
    for step in steps:
        parts = [] if last is None else [f"Observation: {last}"]
        if step.view is not None:
            parts.append(_phone(step.view, step.turn))
        messages.append({"role": "user", "content": "\n\n".join(parts) or f"Turn {step.turn}."})
        answer: dict[str, str] = {"role": "assistant", "content": step.action.raw or ""}
        if step.action.reasoning:
            answer["reasoning_content"] = step.action.reasoning
        messages.append(answer)
        last = step.observation
    return messages


def _phone(view: ViewRecord, turn: int) -> str:
    """The phone as the user saw it, in the words of the user's prompt (not its exact text)."""
    lines = [f"Turn {turn}. Current time: {view.time}"]
    lines.append(
        f"Current app: {view.app}; screen: {view.screen}" if view.app else "You are on the home screen."
    )
    if view.notifications:
        lines.append("New notifications:\n" + "\n".join(f"- {note}" for note in view.notifications))
    if view.pending_proposal:
        lines.append(f"The assistant proposes (accept_proposal or reject_proposal): {view.pending_proposal}")
    if view.tools:
        lines.append("Available tools: " + ", ".join(view.tools))
    return "\n".join(lines)
