"""The README's Python example runs as written."""

from __future__ import annotations

import re
from pathlib import Path

README = Path(__file__).resolve().parents[1] / "README.md"


def test_readme_python_example_runs() -> None:
    blocks = re.findall(r"```python\n(.*?)```", README.read_text(encoding="utf-8"), re.S)
    assert blocks, "the README shows how to use the environment from Python"
    namespace: dict[str, object] = {}
    exec(compile(blocks[0], str(README), "exec"), namespace)
    env = namespace["env"]
    assert [(e.actor, e.tool, e.ok) for e in env.log] == [  # type: ignore[attr-defined]
        ("env", "receive_email", True),
        ("user", "open_app", True),
        ("user", "open_email_by_index", True),
        ("assistant", "search_emails", True),
        ("assistant", "send_message_to_user", True),
        ("user", "accept_proposal", True),
    ]
