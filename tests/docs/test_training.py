"""The training guide's examples run as written (those that need no model server), and all compile."""

from __future__ import annotations

import ast
import re
from pathlib import Path

import pytest

from pare.scenarios.library import splits

GUIDE = Path(__file__).parents[2] / "docs" / "training.md"


def _blocks() -> list[str]:
    return re.findall(r"```python\n(.*?)```", GUIDE.read_text(encoding="utf-8"), re.S)


def _run(block: str, capsys: pytest.CaptureFixture[str]) -> str:
    exec(compile(block, str(GUIDE), "exec"), {})
    return capsys.readouterr().out


def test_every_python_block_compiles() -> None:
    for block in _blocks():
        compile(block, str(GUIDE), "exec")


def test_the_gymnasium_example_plays_an_episode_to_its_verdict(capsys: pytest.CaptureFixture[str]) -> None:
    pytest.importorskip("gymnasium")
    (block,) = [b for b in _blocks() if "env.step(action)" in b]
    scenario_id, success, goal_rate = _run(block, capsys).split()
    assert scenario_id in splits()["smoke"]
    assert success in ("True", "False") and 0.0 <= float(goal_rate) <= 1.0


def test_the_async_example_plays_eight_episodes_at_once(capsys: pytest.CaptureFixture[str]) -> None:
    (block,) = [b for b in _blocks() if "asyncio.gather" in b]
    verdicts = ast.literal_eval(_run(block, capsys).strip())
    assert len(verdicts) == 8 and all(isinstance(verdict, bool) for verdict in verdicts)
