"""How long a proposal must wait for a user who checks before answering: the library's success by expiry.

    python benchmarks/proposal_expiry.py [--checks 0,1,2,3,4,5] [--ttl 2,3,4,6,none] [PATHS ...]

A careful user verifies a proposal before answering it: going home, opening the app that holds the fact
and opening the item takes three actions, and each turn gives the user one. This script plays every
scenario with the oracle assistant and an oracle user that takes ``k`` harmless actions between a
proposal's arrival and its answer, for each proposal lifetime (``protocol.proposal_ttl_turns``; ``none``:
never withdrawn, the paper's setting), and prints the share of scenarios that still succeed. A lifetime
that fails users who check three times is too short for a careful user; the longer one pays for it only
where a proposal is ignored (the assistant may propose again only once the old one is gone). Prints
numbers only; no assertion.
"""

from __future__ import annotations

import argparse
import asyncio
import time

from pare.agents.policy import Action
from pare.bench import EpisodeSettings, arun_episode
from pare.env import UserView
from pare.env.views import ToolResult
from pare.scenarios import OracleAssistant, OracleUser, library, load_scenarios
from pare.scenarios.model import Scenario
from pare.scenarios.oracle import HARMLESS_STEP


class CheckingUser(OracleUser):
    """The oracle user, who takes ``checks`` harmless actions before answering each proposal."""

    def __init__(self, scenario: Scenario, checks: int) -> None:
        super().__init__(scenario)
        self.checks = checks
        self._looked: dict[str, int] = {}

    async def step(self, view: UserView, previous: ToolResult | None) -> Action:
        pending = view.pending_proposal
        if pending is not None and self._looked.get(pending, 0) < self.checks:
            self._looked[pending] = self._looked.get(pending, 0) + 1
            return Action(HARMLESS_STEP)
        return await super().step(view, previous)


async def success_share(scenarios: list[Scenario], checks: int, ttl: int | None) -> float:
    won = 0
    for scenario in scenarios:
        settings = EpisodeSettings(proposal_ttl_turns=ttl)
        result = await arun_episode(
            scenario, CheckingUser(scenario, checks), OracleAssistant(scenario), settings
        )
        won += result.outcome.success
    return won / len(scenarios)


def main() -> None:
    parser = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    parser.add_argument("--checks", default="0,1,2,3,4,5", help="Actions taken before answering.")
    parser.add_argument("--ttl", default="2,3,4,6,none", help="Proposal lifetimes in turns; none: never.")
    parser.add_argument("paths", nargs="*", help="Scenario files (default: the library).")
    options = parser.parse_args()
    scenarios = load_scenarios(options.paths) if options.paths else list(library().values())
    proposing = sorted((s for s in scenarios if s.kind == "proposal"), key=lambda s: s.id)
    checks = [int(value) for value in options.checks.split(",")]
    ttls = [None if value == "none" else int(value) for value in options.ttl.split(",")]
    began = time.perf_counter()
    print(f"{len(proposing)} proposal scenarios; share that succeed when the user checks k times first")
    print("k \\ ttl " + "".join(f"{'none' if ttl is None else ttl:>8}" for ttl in ttls))
    for k in checks:
        shares = [asyncio.run(success_share(proposing, k, ttl)) for ttl in ttls]
        print(f"{k:>7} " + "".join(f"{share:>8.1%}" for share in shares))
    print(f"({time.perf_counter() - began:.1f} s)")


if __name__ == "__main__":
    main()
