"""The local chat server plays the generator and the judge from scripted answers; no network."""

from __future__ import annotations

import re
from collections.abc import Iterator, Mapping, Sequence
from pathlib import Path
from typing import Any

import pytest

from pare.agents.models import ModelConfig
from pare.generate import GenerateConfig
from pare.generate.sections import STAGE_KEYS, STAGES, split_sections
from pare.testing import ChatServer, failure
from pare.testing.generation import ScriptedGeneration
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


ScriptedGenerator = ScriptedGeneration


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
