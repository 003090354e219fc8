"""The generator's and the judge's prompts, rendered from the Jinja templates beside this module."""

from __future__ import annotations

import functools
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from jinja2 import Environment

from pare.agents.prompts import template_environment
from pare.generate.context import Example, app_line, apps_reference, schema_text
from pare.generate.sections import STAGE_KEYS, STAGES

TEMPLATES = Path(__file__).parent / "templates"

SYSTEM_OPENING = "You write scenarios for PARE-Bench"
"""How the generator's system prompt starts (a test server tells the generator's calls by it)."""
JUDGE_OPENING = "You decide whether a new benchmark scenario"
"""How the uniqueness judge's prompt starts."""
STAGE_HEADINGS = {
    "story": "# Stage 1 of 4: the story",
    "seed": "# Stage 2 of 4: the apps' initial data",
    "events": "# Stage 3 of 4: the events and the oracle",
    "validation": "# Stage 4 of 4: the validation",
}
"""How each stage's first message starts (the templates' first lines; a test keeps them in step)."""


@functools.cache
def _templates() -> Environment:
    return template_environment(TEMPLATES)


def render(name: str, **values: Any) -> str:
    """Render the template ``name`` with ``values``."""
    text: str = _templates().get_template(name).render(**values)
    return text


def system_prompt(example: Example | None) -> str:
    """The generator's system prompt: its task, the rules, the gate, the JSON Schema and the example."""
    return render("system.j2", schema=schema_text(), example=example)


def stage_prompt(
    stage: str,
    *,
    apps: Sequence[str],
    candidate: str,
    index: int = 1,
    count: int = 1,
    tag: str = "",
    tags: Sequence[str] = (),
    difficulty: str | None = None,
    difficulties: Sequence[str] = (),
    taken: Sequence[str] = (),
    turns: str = "",
) -> str:
    """The first message of ``stage``: what it must write, with what it needs (earlier sections, the apps'
    seed formats, screens and tools, and ``turns``: what the runs played so far took).
    """
    if stage == "story":
        return render(
            "story.j2",
            apps=apps,
            app_lines=[app_line(app) for app in apps],
            index=index,
            count=count,
            tag=tag,
            tags=tags,
            difficulty=difficulty,
            difficulties=difficulties,
            taken=taken,
        )
    reference = apps_reference(apps, seed=stage != "events", tools=stage != "seed")
    return render(f"{stage}.j2", apps=apps, candidate=candidate, reference=reference, turns=turns)


def feedback_prompt(stage: str, problems: Sequence[str], *, played: bool, left: int, turns: str = "") -> str:
    """What goes back to the model when a stage's answer has problems (with ``turns``, the turns the
    played runs took).
    """
    position = STAGES.index(stage)
    earlier = [key for previous in STAGES[1:position] for key in STAGE_KEYS[previous]]
    return render(
        "feedback.j2",
        stage=stage,
        problems=problems,
        played=played,
        keys=STAGE_KEYS[stage],
        earlier=earlier,
        left=left,
        turns=turns,
    )


def judge_prompt(candidate: Any, neighbours: Sequence[Any]) -> str:
    """The uniqueness judge's prompt: the candidate's story and its nearest library stories."""
    return render("judge.j2", candidate=candidate, neighbours=neighbours)
