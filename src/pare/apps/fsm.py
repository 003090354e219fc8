"""The user FSM of an app, read from its declarations: listing and Mermaid export."""

from __future__ import annotations

from dataclasses import dataclass

from pare.apps.base import App
from pare.apps.screens import BACK, STAY


@dataclass(frozen=True, slots=True)
class Edge:
    """One declared transition: ``action`` on screen ``source`` may lead to ``target``."""

    source: str
    action: str
    target: str
    via_back: bool = False
    """The action returns to the previous screen; ``target`` is one of the screens it can be."""


def transitions(app: type[App]) -> list[Edge]:
    """Every edge of the app's FSM, including where a ``BACK`` action can land.

    A ``BACK`` action on screen S returns to whichever screen led to S, so it becomes one edge to each
    screen with an action declared to lead to S.
    """
    parents: dict[str, list[str]] = {}
    for screen in app.screens:
        for spec in screen.actions.values():
            for target in spec.leads_to:
                if target not in (STAY, BACK) and target != screen.screen_name():
                    parents.setdefault(target, [])
                    if screen.screen_name() not in parents[target]:
                        parents[target].append(screen.screen_name())
    edges: list[Edge] = []
    for screen in app.screens:
        name = screen.screen_name()
        for spec in screen.actions.values():
            for target in spec.leads_to:
                if target == STAY:
                    continue
                if target == BACK:
                    edges.extend(
                        Edge(name, spec.name, parent, via_back=True) for parent in parents.get(name, [])
                    )
                else:
                    edges.append(Edge(name, spec.name, target))
    return edges


def to_mermaid(app: type[App]) -> str:
    """A Mermaid ``stateDiagram-v2`` of the app's screens.

    Actions that keep the user on a screen are listed inside the screen's box; actions that move are
    arrows (``(back)`` marks a return to the previous screen). ``go_back`` from any screen with a previous
    one, and the shell's ``go_home`` / ``switch_app``, are implied and not drawn.
    """
    lines = ["stateDiagram-v2", f"    %% {app.title} ({app.name}): user screens and actions"]
    root = app.screens[0].screen_name()
    lines.append(f"    [*] --> {root}")
    for screen in app.screens:
        name = screen.screen_name()
        for spec in screen.actions.values():
            if STAY in spec.leads_to:
                lines.append(f"    {name} : {spec.name}")
    for edge in transitions(app):
        label = f"{edge.action} (back)" if edge.via_back else edge.action
        lines.append(f"    {edge.source} --> {edge.target} : {label}")
    return "\n".join(lines) + "\n"
