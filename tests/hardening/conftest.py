"""Shared pieces of the hostile-input tests: no network, a key variable, a scenario file, strict JSON."""

from __future__ import annotations

import json
import re
from pathlib import Path
from typing import Any, NoReturn

import pytest

from tests.agents.conftest import no_network

__all__ = ["KEY_VARIABLE", "example_scenario", "no_network", "strict_json"]

KEY_VARIABLE = "PARE_TEST_API_KEY"
GUIDE = Path(__file__).parents[2] / "docs" / "writing-scenarios.md"


@pytest.fixture(autouse=True)
def api_key(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv(KEY_VARIABLE, "sk-pare-hardening-test")


@pytest.fixture
def example_scenario(tmp_path: Path) -> Path:
    """The scenario guide's worked example, written to a file (a small scenario that passes the gate)."""
    text = GUIDE.read_text(encoding="utf-8")
    found = re.search(r"```yaml\n(.*?)```", text[text.index("## A complete example") :], re.S)
    assert found is not None
    path = tmp_path / "dentist_example.yaml"
    path.write_text(found.group(1), encoding="utf-8")
    return path


def _no_constant(name: str) -> NoReturn:
    raise AssertionError(f"{name} is not JSON")


def strict_json(text: str) -> Any:
    """Parse ``text`` as standard JSON: NaN and Infinity are refused, as every other reader refuses them."""
    return json.loads(text, parse_constant=_no_constant)
