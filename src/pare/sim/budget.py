"""The turn protocol's limits: a small module of its own, so that the scenario loader (which checks
interventions against them) does not import the actors.
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True, slots=True)
class TurnBudget:
    """The turn protocol's limits, which each actor is told: how long the session lasts, how many
    actions a turn allows, how long a proposal waits for its answer.
    """

    max_turns: int = 10
    user_steps: int = 1
    observe_steps: int = 5
    execute_steps: int = 10
    proposal_ttl_turns: int = 4
    turn_minutes: float = 1.0
    """Simulated minutes one turn takes when someone acted (time jumps further when everyone waits)."""


DEFAULT_BUDGET = TurnBudget()
