"""Tests under tests/results cannot reach the network either: the loopback-only guard of tests/agents."""

from __future__ import annotations

from tests.agents.conftest import no_network

__all__ = ["no_network"]  # an autouse fixture: imported here, it guards every test in this folder
