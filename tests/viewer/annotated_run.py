"""A run to annotate: the dentist scenario three times, the user simulator accepting in runs 1 and 3 and
rejecting in run 2, a judge that passes every text (so runs 1 and 3 each have one judged text).
"""

from __future__ import annotations

from pathlib import Path

from pare.agents.policy import Action, UserPolicy
from pare.bench.policies import PolicyContext
from pare.cli import main
from pare.env import ToolResult, UserView
from pare.scenarios.oracle import OracleUser

SCENARIO = "dentist_moves_checkup"


class RejectingUser(OracleUser):
    """The oracle user who turns every proposal down."""

    async def step(self, view: UserView, previous: ToolResult | None) -> Action:
        if view.pending_proposal is not None:
            return Action("reject_proposal", {"reason": "No, thanks."})
        return await super().step(view, previous)


def rejects_in_run_two(context: PolicyContext) -> UserPolicy:
    """The oracle user, but rejecting in run 2."""
    return RejectingUser(context.scenario) if context.run == 2 else OracleUser(context.scenario)


def make_annotated_run(folder: Path) -> Path:
    """Play the run into ``folder`` and return it."""
    arguments = ["run", "-s", SCENARIO, "--runs", "3", "--no-progress", "--output", str(folder)]
    arguments += ["--user-policy", f"{__name__}:rejects_in_run_two"]
    arguments += ["--set", "policies.judge=tests.bench.custom_policies:always_yes"]
    assert main(arguments) == 0
    return folder
