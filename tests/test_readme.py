"""The README's Python examples run as written."""

from __future__ import annotations

import re
from pathlib import Path

README = Path(__file__).resolve().parents[1] / "README.md"


def _blocks() -> list[str]:
    return re.findall(r"```python\n(.*?)```", README.read_text(encoding="utf-8"), re.S)


def _run_block(containing: str) -> dict[str, object]:
    (block,) = [b for b in _blocks() if containing in b and "LLMUser" not in b]
    namespace: dict[str, object] = {}
    exec(compile(block, str(README), "exec"), namespace)
    return namespace


def test_readme_environment_example_runs() -> None:
    env = _run_block("Environment(")["env"]
    assert [(e.actor, e.tool, e.ok) for e in env.log] == [  # type: ignore[attr-defined]
        ("env", "receive_email", True),
        ("user", "open_app", True),
        ("user", "open_email_by_index", True),
        ("assistant", "search_emails", True),
        ("assistant", "send_message_to_user", True),
        ("user", "accept_proposal", True),
    ]


def test_readme_scenario_example_runs() -> None:
    result = _run_block("run_episode(")["result"]
    assert result.success  # type: ignore[attr-defined]


def test_every_python_block_compiles() -> None:
    for block in _blocks():
        compile(block, str(README), "exec")  # the model-backed example needs a model, so it only compiles
