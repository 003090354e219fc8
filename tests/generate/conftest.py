"""The local chat server plays the generator and the judge from scripted answers; no network."""

from __future__ import annotations

import re
from collections.abc import Iterator, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import pytest

from pare.agents.models import ModelConfig
from pare.generate import GenerateConfig
from pare.generate.prompts import JUDGE_OPENING, SYSTEM_OPENING
from pare.generate.sections import STAGE_KEYS, STAGES, split_sections
from pare.testing import ChatServer, Reply, completion, failure
from tests.agents.conftest import no_network

__all__ = ["no_network"]

GUIDE = Path(__file__).parents[2] / "docs" / "writing-scenarios.md"
BENCH = Path(__file__).parents[2] / "src" / "pare" / "scenarios" / "bench"


def example_text() -> str:
    """The scenario guide's worked example (a small scenario that passes the gate)."""
    text = GUIDE.read_text(encoding="utf-8")
    found = re.search(r"```yaml\n(.*?)```", text[text.index("## A complete example") :], re.S)
    assert found is not None
    return found.group(1)


def example_answers(**replace: str) -> dict[str, str]:
    """The worked example cut into the four stages' answers, each a fenced YAML block after a sentence;
    ``replace`` substitutes text in the whole example first (``old=new`` pairs as keyword names won't do,
    so use :func:`with_replaced`).
    """
    sections = split_sections(example_text(), [k for s in STAGES for k in STAGE_KEYS[s]]).sections
    answers = {}
    for stage in STAGES:
        body = "".join(sections[key] for key in STAGE_KEYS[stage] if key in sections)
        answers[stage] = f"Here is the {stage} section.\n\n```yaml\n{body}```\n"
    return answers


def with_replaced(answers: Mapping[str, str], pairs: Sequence[tuple[str, str]]) -> dict[str, str]:
    """``answers`` with each ``(old, new)`` replaced in every stage's text."""
    changed = dict(answers)
    for stage, text in changed.items():
        for old, new in pairs:
            text = text.replace(old, new)
        changed[stage] = text
    return changed


@dataclass
class ScriptedGenerator:
    """A responder: the generator's answers per candidate and stage, one per attempt (the last one repeats),
    and the judge's verdicts in order (the last one repeats).
    """

    scripts: dict[int, dict[str, list[str]]]
    verdicts: list[str] = field(default_factory=lambda: ['{"duplicate": false, "reason": "new"}'])
    judge_calls: int = 0

    def _index(self, messages: Sequence[Mapping[str, Any]]) -> int:
        first = str(messages[1]["content"])
        found = re.search(r"\(candidate (\d+) of \d+\)", first)
        if found:
            return int(found.group(1))
        scenario_id = re.search(r"^id: (\S+)", first, re.M)
        assert scenario_id is not None, first[:300]
        for index, stages in self.scripts.items():
            if re.search(rf"^id: {re.escape(scenario_id.group(1))}\s*$", stages["story"][-1], re.M):
                return index
        raise AssertionError(f"no script writes id {scenario_id.group(1)}")

    def __call__(self, body: dict[str, Any]) -> Reply:
        messages = body["messages"]
        if str(messages[0]["content"]).startswith(JUDGE_OPENING):
            self.judge_calls += 1
            return completion(self.verdicts[min(self.judge_calls, len(self.verdicts)) - 1])
        if not str(messages[0]["content"]).startswith(SYSTEM_OPENING):
            return failure(400, "not a generator conversation")
        stage = re.search(r"# Stage \d of 4: the (\w+)", str(messages[1]["content"]))
        assert stage is not None
        name = {"story": "story", "apps": "seed", "events": "events", "validation": "validation"}[
            stage.group(1)
        ]
        answers = self.scripts[self._index(messages)][name]
        attempt = sum(message["role"] == "assistant" for message in messages)
        return completion(answers[min(attempt, len(answers) - 1)], 1000, 500)


@pytest.fixture
def server() -> Iterator[ChatServer]:
    with ChatServer(lambda body: failure(500, "no script yet")) as chat:
        yield chat


def make_config(server: ChatServer, output: Path, library: Path, **settings: Any) -> GenerateConfig:
    """A batch against the local server, comparing with ``library``."""
    model = ModelConfig(
        model="pare-generator",
        api_base=server.base_url,
        api_key_env=None,
        max_retries=0,
        prices={"input": 1.0, "output": 2.0},
    )
    values: dict[str, Any] = {
        "apps": ["email", "calendar"],
        "count": 1,
        "output": str(output),
        "generator": model,
        "library": [str(library)],
        "concurrency": 2,
        **settings,
    }
    return GenerateConfig.model_validate(values)


@pytest.fixture
def library(tmp_path: Path) -> Path:
    """A small library of two scenarios far from the worked example's story."""
    folder = tmp_path / "library"
    folder.mkdir()
    for name in ("bounced_email_typo_resend_to_contact", "book_club_pick_paperback"):
        (folder / f"{name}.yaml").write_text((BENCH / f"{name}.yaml").read_text(encoding="utf-8"))
    return folder
