"""Fixtures of the viewer's tests: two run folders made once per session with ``pare run``, a sweep, and
the same loopback-only network guard as the other tests.
"""

from __future__ import annotations

import os
from collections.abc import Iterator
from pathlib import Path

import pytest

from pare.cli import main
from tests.agents.conftest import no_network
from tests.viewer.runs import KEY_VARIABLE, Runs, make_runs, make_world_run

__all__ = ["no_network"]  # an autouse fixture: imported here, it guards every test in this folder


@pytest.fixture(scope="session")
def runs(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Runs]:
    """An oracle run and a model-backed run (failing checks) of two scenarios, two runs each."""
    os.environ.setdefault(KEY_VARIABLE, "not-a-real-key")
    yield make_runs(tmp_path_factory.mktemp("runs"))


@pytest.fixture(scope="session")
def sweep(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A sweep of the oracle over two tool-failure probabilities, one scenario, one run."""
    folder = tmp_path_factory.mktemp("sweep") / "sweep"
    spec = folder.parent / "sweep.yaml"
    spec.write_text(
        "base:\n  scenarios: {ids: [dentist_moves_checkup]}\n  runs: 1\n"
        "grid:\n  world.tool_failure_probability: [0.0, 0.5]\n"
        f"output: {folder}\n",
        encoding="utf-8",
    )
    assert main(["sweep", "-c", str(spec), "--no-progress"]) == 0
    return folder


@pytest.fixture(scope="session")
def world_run(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The oracle on a scenario whose events make messages in the chat the assistant writes in."""
    return make_world_run(tmp_path_factory.mktemp("world") / "oracle")
