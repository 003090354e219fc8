"""Run folders for the viewer's tests, made with ``pare run`` like a user would.

Two configurations of the same two scenarios: the oracle (every goal met), and model-backed actors served
by local chat servers (:func:`pare.testing.proactive_play`): the assistant proposes a vague task, the user
accepts it, and the assistant reports without doing anything, so checks fail with their details.
"""

from __future__ import annotations

import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

from pare.cli import main
from pare.testing import ChatServer, proactive_play

SCENARIOS = ("dentist_moves_checkup", "five_a_side_kickoff_moved")
KEY_VARIABLE = "PARE_VIEWER_TEST_KEY"
WORLD_SCENARIO = "climbing_session_clash_find_tuesday"
"""Three friends' messages arrive, the assistant writes in the same group chat, and a friend replies."""


@dataclass(frozen=True)
class Runs:
    """The two run folders."""

    oracle: Path
    models: Path


def make_runs(folder: Path, runs: int = 2) -> Runs:
    """Run the oracle and the scripted models over :data:`SCENARIOS` into ``folder``.

    The caller sets the environment variable :data:`KEY_VARIABLE` (any value: the servers ignore it).
    """
    selection = [argument for scenario in SCENARIOS for argument in ("-s", scenario)]
    common = ["run", "--no-progress", "--runs", str(runs), *selection]
    oracle = folder / "oracle"
    assert main([*common, "--output", str(oracle)]) == 0
    models = folder / "models"
    with ChatServer(proactive_play()) as user, ChatServer(proactive_play()) as assistant:
        argv = [*common, "--output", str(models)]
        argv += ["--user-model", "test-user", "--user-endpoint", user.base_url]
        argv += ["--assistant-model", "test-assistant", "--assistant-endpoint", assistant.base_url]
        for role in ("user", "assistant"):
            argv += ["--set", f"models.{role}.api_key_env={KEY_VARIABLE}"]
            argv += ["--set", f"models.{role}.prices={{input: 1.0, output: 2.0}}"]
        argv += ["--cache", "off"]
        assert main(argv) == 0
    return Runs(oracle, models)


def make_world_run(folder: Path) -> Path:
    """The oracle on :data:`WORLD_SCENARIO`, one run: items made by the world beside the assistant's.

    Run in its own process, as a user runs it: the browser tests may ask for it while Playwright's
    event loop is running, where ``pare run`` could not start its own.
    """
    command = [sys.executable, "-m", "pare", "run", "--no-progress", "--runs", "1", "-s", WORLD_SCENARIO]
    subprocess.run([*command, "--output", str(folder)], check=True, capture_output=True)
    return folder
