"""A model as the judge of free-text checks (``judge`` checks in scenarios).

The judge reads one criterion, one text and the scenario's facts, if it gives any, and answers YES or NO
with one sentence saying why. The verdict is the answer's first word: anything but a clear yes counts as
NO, so a check passes only on a clear yes. The answer, the reason and the model are kept with the check's
result in the trajectory. Scenarios always carry a deterministic fallback, used when no judge is configured.

The judge is awaited in the episode's event loop: in a run, its model is the run's shared client for the
judge role, so its calls wait for the same per-endpoint limit as every other role's and go through the
same call cache.
"""

from __future__ import annotations

import re
from collections.abc import Sequence
from dataclasses import replace

from pare.agents.llm import ChatModel
from pare.agents.models.types import ChatMessage
from pare.scenarios.checks import JudgeVerdict

JUDGE_PROMPT = (
    "You check whether a text written by an assistant on a user's behalf meets a criterion. Read the "
    "criterion and the text, then answer YES if the text clearly meets the criterion, NO otherwise, as the "
    "first word of your answer, followed by one sentence saying why. When facts are given, they are what "
    "is true: a text that states a detail (a time, a date, a place, a name, a number, a price) that the "
    "facts contradict or do not contain has invented it, and does not meet the criterion."
)
_VERDICT = re.compile(r"^\W*(yes|no)\b", re.IGNORECASE)
_REASON_LENGTH = 300
"""The longest reason kept (a model that ignores "one sentence" does not fill the trajectory)."""


def judge_request(criterion: str, text: str, facts: Sequence[str] = ()) -> list[ChatMessage]:
    """The conversation that asks the judge about one ``text``."""
    question = f"Criterion: {criterion}\n\n"
    if facts:
        question += "Facts:\n" + "".join(f"- {fact}\n" for fact in facts) + "\n"
    return [
        ChatMessage(role="system", content=JUDGE_PROMPT),
        ChatMessage(role="user", content=f"{question}Text:\n{text}"),
    ]


def read_verdict(answer: str) -> JudgeVerdict:
    """The verdict in a judge's ``answer``: a pass only when its first word is yes; the reason is what
    follows it, on one line (empty when the answer gives none).
    """
    found = _VERDICT.match(answer)
    passed = found is not None and found.group(1).lower() == "yes"
    rest = answer[found.end() :] if found is not None else answer
    reason = " ".join(rest.split()).lstrip(" .,:;-\u2013\u2014")
    if len(reason) > _REASON_LENGTH:
        reason = reason[: _REASON_LENGTH - 3].rstrip() + "..."
    return JudgeVerdict(passed, reason, answer)


class ModelJudge:
    """A :class:`pare.scenarios.checks.Judge` backed by a model (any :class:`ChatModel`), named
    ``model_name`` in the verdicts it gives.
    """

    def __init__(self, model: ChatModel, model_name: str = "") -> None:
        self.model = model
        self.model_name = model_name

    async def __call__(self, criterion: str, text: str, facts: Sequence[str] = ()) -> JudgeVerdict:
        """Whether ``text`` meets ``criterion`` given ``facts``, in the model's opinion, and why."""
        completion = await self.model.complete(judge_request(criterion, text, facts))
        return replace(read_verdict((completion.text or "").strip()), model=self.model_name)
