"""A model as the judge of free-text checks (``judge`` checks in scenarios).

The judge reads one criterion and one text and answers YES or NO. Anything else counts as NO: a check
passes only on a clear yes. Scenarios always carry a deterministic fallback, used when no judge is
configured.
"""

from __future__ import annotations

import asyncio
import re

from pare.agents.llm import ChatModel
from pare.agents.models.types import ChatMessage

JUDGE_PROMPT = (
    "You check whether a text written by an assistant on a user's behalf meets a criterion. Read the "
    "criterion and the text, then answer with one word: YES if the text clearly meets the criterion, NO "
    "otherwise. Do not explain."
)
_VERDICT = re.compile(r"^\W*(yes|no)\b", re.IGNORECASE)


class ModelJudge:
    """A :data:`pare.scenarios.checks.Judge` backed by a model (any :class:`ChatModel`).

    Called synchronously by the checks; the episode loop evaluates checks in a worker thread when a judge
    is set, so the model call runs in its own event loop there.
    """

    def __init__(self, model: ChatModel) -> None:
        self.model = model
        self.verdicts: list[tuple[str, str, bool]] = []
        """Every (criterion, answer, verdict), for reports."""

    def __call__(self, criterion: str, text: str) -> bool:
        """Whether ``text`` meets ``criterion``, in the model's opinion."""
        messages = [
            ChatMessage(role="system", content=JUDGE_PROMPT),
            ChatMessage(role="user", content=f"Criterion: {criterion}\n\nText:\n{text}"),
        ]
        completion = asyncio.run(self.model.complete(messages))
        answer = (completion.text or "").strip()
        found = _VERDICT.match(answer)
        verdict = found is not None and found.group(1).lower() == "yes"
        self.verdicts.append((criterion, answer, verdict))
        return verdict
