"""What the generator's prompts carry: the scenario format, a worked example, and each app's seed format,
screens and tools (the data ``pare apps show APP [--seed]`` prints), as plain text.
"""

from __future__ import annotations

import functools
import json
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from pare.apps.registry import get_app_class
from pare.apps.screens import BACK, STAY
from pare.scenarios.model import Scenario
from pare.scenarios.schema import scenario_json_schema
from pare.scenarios.seed_format import seed_format

SHELL_APPS = ("system", "agent_ui", "files")
"""The apps on every phone, whose tools every stage may use."""


@dataclass(frozen=True, slots=True)
class Example:
    """A library scenario shown to the generator as a worked example."""

    scenario_id: str
    text: str


REPEATED_DESCRIPTION = 120
"""A description at least this long is written out once in the generator's schema; later places say
where it is (the matcher's description alone is about 2,000 characters, at eight places)."""


@functools.cache
def schema_text() -> str:
    """The JSON Schema of scenario files, compact (it travels in every stage's prompt), each long
    description written once.
    """
    return json.dumps(describe_once(scenario_json_schema()), separators=(",", ":"), ensure_ascii=False)


def describe_once(schema: Any) -> Any:
    """``schema`` with each long description said at its first place only (later places read "Same as the
    description of X.y.", ``$defs`` names and properties as a model reads them), and without the titles
    that only repeat the name they are under.
    """
    first: dict[str, str] = {}

    def walk(node: Any, place: tuple[str, ...]) -> Any:
        if isinstance(node, list):
            return [walk(item, place) for item in node]
        if not isinstance(node, dict):
            return node
        copy: dict[str, Any] = {}
        for key, value in node.items():
            if key == "title" and place and value in (place[-1], place[-1].replace("_", " ").title()):
                continue  # a title made from the name it is under says nothing more
            if key == "description" and isinstance(value, str) and len(value) >= REPEATED_DESCRIPTION:
                named = ".".join(place)
                said = first.setdefault(value, named)
                copy[key] = value if said == named else f"Same as the description of {said}."
            elif key in ("$defs", "properties"):
                copy[key] = {name: walk(item, (*place, name)) for name, item in value.items()}
            else:
                copy[key] = walk(value, place)
        return copy

    return walk(schema, ())


def worked_example(
    apps: Sequence[str], library: Sequence[Scenario], files: dict[str, Path]
) -> Example | None:
    """The library scenario that shares most of ``apps`` (the shortest file among equals), as its text."""
    wanted = set(apps)
    best: tuple[int, int, str] | None = None
    for scenario in library:
        path = files.get(scenario.id)
        if path is None:
            continue
        text = path.read_text(encoding="utf-8")
        key = (-len(wanted & set(scenario.apps)), len(text), scenario.id)
        if best is None or key < best:
            best = key
    if best is None:
        return None
    text = files[best[2]].read_text(encoding="utf-8")
    body = "\n".join(line for line in text.splitlines() if not line.startswith("# yaml-language-server"))
    return Example(best[2], body.strip() + "\n")


@functools.cache
def app_reference(app: str) -> str:
    """One app as the generator needs it: what it is, its screens with the user's actions (kind and
    target screen), and its agent tools (``app__tool`` signatures with descriptions).
    """
    cls = get_app_class(app)
    lines = [f"### {cls.title} ({cls.name}): {cls.description}".rstrip(": ")]
    if cls.screens:
        lines.append("User screens:")
        for screen in cls.screens:
            lines.append(f"- screen {screen.screen_name()}:")
            for spec in screen.actions.values():
                targets = ", ".join({STAY: "(stay)", BACK: "(back)"}.get(t, t) for t in spec.leads_to)
                lines.append(f"  - {spec.signature} [{spec.kind}] -> {targets}")
    lines.append("Agent tools:")
    for spec in cls.tools.values():
        actors = ",".join(sorted(spec.actors))
        signature = spec.qualified_name + spec.signature[len(spec.name) :]
        lines.append(f"- {signature} [{spec.kind}; {actors}]: {spec.description}")
    return "\n".join(lines)


def app_line(app: str) -> str:
    """``app: what it is``, for the story stage."""
    cls = get_app_class(app)
    return f"{cls.name}: {cls.description}"


@functools.cache
def seed_reference(app: str) -> str:
    """The seed data format of ``app`` (``pare apps show APP --seed``)."""
    return "\n".join(seed_format(app))


REFERENCE_KEY = (
    "How to read the apps below. User screens: root first; each user action as "
    "`name(args) [kind] -> screen`. Agent tools: `app__tool(args) [kind; actors]` (the assistant in "
    "execute mode reads and writes, in observe mode only reads; the world's events use the env tools)."
)
"""Said once above the apps' references, not in each app's."""


def apps_reference(apps: Sequence[str], *, seed: bool, tools: bool) -> str:
    """The chosen apps' references (seed formats, screens and tools), with the phone's core apps' tools."""
    parts = [REFERENCE_KEY] if tools else []
    for app in apps:
        if tools:
            parts.append(app_reference(app))
        if seed:
            parts.append(f"Seed format of {app}:\n```yaml\n{seed_reference(app)}\n```")
    if tools:
        parts.extend(app_reference(app) for app in SHELL_APPS if app not in apps)
    return "\n\n".join(parts)
