"""A candidate scenario as the four stages write it: top-level sections of one YAML file.

Each stage answers with some of the file's top-level keys (the story stage ``id`` to ``user``, the seed
stage ``seed``, and so on). The candidate is the text of every section written so far, joined in the
file's order, so that anchors written in one stage (an intervention under ``oracle``) can be merged in a
later one (``variants``). Sections a stage has not written yet are filled with placeholders when the
candidate is loaded, and the problems found in them are left out.
"""

from __future__ import annotations

import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

STAGES: tuple[str, ...] = ("story", "seed", "events", "validation")
"""The four stages, in order: the story; the apps' initial data; the events with the oracle's actions;
the validation (goals and variants)."""

STAGE_KEYS: dict[str, tuple[str, ...]] = {
    "story": (
        "format",
        "id",
        "title",
        "story",
        "tags",
        "difficulty",
        "kind",
        "end_when_met",
        "apps",
        "start",
        "user",
    ),
    "seed": ("seed",),
    "events": ("events", "oracle"),
    "validation": ("goals", "variants"),
}
"""The top-level keys each stage writes."""

ORDER: tuple[str, ...] = tuple(key for stage in STAGES for key in STAGE_KEYS[stage])
"""Every top-level key of a scenario file, in the order candidates are written."""

PLACEHOLDERS: dict[str, str] = {
    "oracle": "oracle: {interventions: [{proposal: Written by a later stage.}]}\n",
    "goals": (
        "goals:\n  - id: placeholder\n    description: Written by a later stage.\n"
        "    checks: [{action: {tool: agent_ui__send_message_to_user}}]\n"
    ),
}
"""Stand-ins for the required sections a stage has not written yet, so the candidate can be loaded."""

_KEY = re.compile(r"^([A-Za-z_][A-Za-z0-9_]*)\s*:")
_FENCE = re.compile(r"```[ \t]*(?:ya?ml)?[ \t]*\n(.*?)```", re.S | re.I)


def stage_of(key: str) -> str | None:
    """The stage that writes top-level ``key`` (``None`` for a key no stage writes)."""
    return next((stage for stage in STAGES if key in STAGE_KEYS[stage]), None)


def extract_yaml(answer: str) -> str:
    """The YAML in a model's answer: its fenced code blocks joined, or the whole answer without fences."""
    blocks = _FENCE.findall(answer)
    return "\n".join(blocks) if blocks else answer


@dataclass(frozen=True, slots=True)
class Split:
    """An answer cut into its top-level sections, and what is wrong with its shape."""

    sections: dict[str, str]
    problems: tuple[str, ...]


def split_sections(text: str, allowed: Sequence[str]) -> Split:
    """Cut YAML ``text`` into top-level sections (key to its text, comments included); only ``allowed``
    keys may be written, each once.
    """
    sections: dict[str, str] = {}
    problems: list[str] = []
    current: str | None = None
    lines: list[str] = []
    stray: list[str] = []

    def close() -> None:
        if current is not None:
            sections[current] = "\n".join(lines).rstrip() + "\n"

    for line in text.splitlines():
        if line.strip() in ("---", "..."):
            continue
        match = _KEY.match(line)
        if match is not None:
            close()
            current, lines = match.group(1), [line]
            if current in sections:
                problems.append(f"top-level key '{current}' is written twice")
            continue
        if current is None:
            if line.strip() and not line.lstrip().startswith("#"):
                stray.append(line.strip())
            continue
        lines.append(line)
    close()
    if stray:
        problems.append(f"text before the first top-level key is not YAML of this stage: {stray[0]!r}")
    for key in sections:
        if key not in allowed:
            owner = stage_of(key)
            where = f"it belongs to the {owner} stage" if owner else "it is not a field of scenario files"
            problems.append(
                f"top-level key '{key}' cannot be written here ({where}); write only: {', '.join(allowed)}"
            )
    if not sections and not problems:
        problems.append(f"the answer holds no YAML section; write: {', '.join(allowed)}")
    return Split(sections, tuple(problems))


def assemble(sections: Mapping[str, str], *, header: str = "", placeholders: bool = False) -> str:
    """The candidate file: ``header``, then every section in the file's order (placeholders for the
    required sections not written yet, when asked).
    """
    parts = [header] if header else []
    for key in ORDER:
        if key in sections:
            parts.append(sections[key])
        elif placeholders and key in PLACEHOLDERS:
            no_proposal = key == "oracle" and "no_proposal" in sections.get("kind", "")
            parts.append("oracle: {}\n" if no_proposal else PLACEHOLDERS[key])
    return "".join(part if part.endswith("\n") else part + "\n" for part in parts)


def top_key(path: str) -> str:
    """The top-level key a loader problem's path starts with (``seed.email...`` -> ``seed``)."""
    match = re.match(r"[A-Za-z_][A-Za-z0-9_]*", path)
    return match.group(0) if match else ""
