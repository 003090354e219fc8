"""A responder for :class:`~pare.testing.ChatServer` that plays ``pare generate``'s models from a script.

The generator's conversations are told apart by their system prompt, the stage by the heading of the
first message (``# Stage 2 of 4: the apps' initial data``), the candidate by its number in the story
stage's heading and afterwards by the scenario id its story wrote; the answer number within a stage is
the number of answers already in the conversation (a retry gets the next scripted answer, and the last
one repeats). The uniqueness judge's conversations get the scripted verdicts in order.

.. code-block:: python

    from pare.testing import ChatServer
    from pare.testing.generation import ScriptedGeneration

    script = {1: {"story": [story], "seed": [bad_seed, seed], "events": [events], "validation": [goals]}}
    with ChatServer(ScriptedGeneration(script)) as server:
        ...  # pare generate --endpoint server.base_url ...
"""

from __future__ import annotations

import re
import threading
from collections.abc import Mapping, Sequence
from typing import Any

from pare.generate.prompts import JUDGE_OPENING, STAGE_HEADINGS, SYSTEM_OPENING
from pare.testing.chat_server import Reply, completion, failure

NOT_DUPLICATE = '{"duplicate": false, "same_as": null, "reason": "a new situation"}'


class ScriptedGeneration:
    """Answers the generator's stages per candidate from ``scripts`` and the judge from ``verdicts``.

    ``scripts`` maps a candidate's number (from 1) to its answers per stage (``story``, ``seed``,
    ``events``, ``validation``), one per attempt. :attr:`judge_calls` counts the judge's requests.
    """

    def __init__(
        self, scripts: Mapping[int, Mapping[str, Sequence[str]]], verdicts: Sequence[str] = ()
    ) -> None:
        self.scripts = scripts
        self.verdicts = list(verdicts) or [NOT_DUPLICATE]
        self.judge_calls = 0
        self._lock = threading.Lock()

    def _candidate(self, first: str) -> int:
        found = re.search(r"\(candidate (\d+) of \d+\)", first)
        if found:
            return int(found.group(1))
        written = re.search(r"^id: *(\S+)", first, re.M)
        if written is None:
            raise ValueError("the stage's message names no candidate and no scenario id")
        for index, stages in self.scripts.items():
            if any(re.search(rf"^id: *{re.escape(written.group(1))}\s*$", a, re.M) for a in stages["story"]):
                return index
        raise ValueError(f"no scripted story writes the id '{written.group(1)}'")

    def __call__(self, body: dict[str, Any]) -> Reply:
        """Answer one request (see the class docstring)."""
        messages = [m for m in body.get("messages") or () if isinstance(m, dict)]
        opening = str(messages[0].get("content", "")) if messages else ""
        if opening.startswith(JUDGE_OPENING):
            with self._lock:
                self.judge_calls += 1
                verdict = self.verdicts[min(self.judge_calls, len(self.verdicts)) - 1]
            return completion(verdict)
        if not opening.startswith(SYSTEM_OPENING) or len(messages) < 2:
            return failure(400, "ScriptedGeneration answers only pare generate's generator and judge")
        first = str(messages[1].get("content", ""))
        stage = next((name for name, heading in STAGE_HEADINGS.items() if first.startswith(heading)), None)
        if stage is None:
            return failure(400, f"no stage heading at the start of: {first[:80]!r}")
        answers = self.scripts[self._candidate(first)][stage]
        attempt = sum(message.get("role") == "assistant" for message in messages)
        return completion(answers[min(attempt, len(answers) - 1)], 1000, 500)
