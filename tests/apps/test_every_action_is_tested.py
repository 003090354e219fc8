"""A guard: every user action and agent tool of every app is exercised by name in the app's test file.

The app tests call actions and tools by name (``env.call("user", "send", ...)``, ``"email__send_email"``),
so a name missing from ``tests/apps/test_<app>.py`` is an action nobody tests.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from pare.apps.registry import get_app_class, phone_apps

HERE = Path(__file__).parent


@pytest.mark.parametrize("name", phone_apps())
def test_every_action_and_tool_is_named_in_the_apps_tests(name: str) -> None:
    text = (HERE / f"test_{name}.py").read_text(encoding="utf-8")
    cls = get_app_class(name)
    actions = {action for screen in cls.screens for action in screen.actions}
    untested = sorted(a for a in actions if f'"{a}"' not in text and f"'{a}'" not in text)
    assert not untested, f"{name}: screen actions never called in tests: {untested}"
    tools = sorted(
        t for t in cls.tools if f'"{t}"' not in text and f"__{t}" not in text and f"{t}(" not in text
    )
    assert not tools, f"{name}: agent tools never called in tests: {tools}"
