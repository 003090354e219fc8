"""The generation guide names only options the commands have."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from pare.cli import main

GUIDE = Path(__file__).parents[2] / "docs" / "generating-scenarios.md"


def _options(argv: list[str], capsys: pytest.CaptureFixture[str]) -> set[str]:
    assert main([*argv, "--help"]) == 0
    return set(re.findall(r"--[a-z][a-z-]*", capsys.readouterr().out))


def test_every_option_the_guide_names_exists(
    monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    monkeypatch.setenv("COLUMNS", "250")
    known = _options(["generate"], capsys) | _options(["scenarios", "review"], capsys)
    known |= _options(["apps", "show"], capsys)  # the guide points at `pare apps show APP --seed`
    named = set(re.findall(r"`(--[a-z][a-z-]*)", GUIDE.read_text(encoding="utf-8")))
    named |= set(re.findall(r" (--[a-z][a-z-]*)", GUIDE.read_text(encoding="utf-8")))
    assert named <= known, named - known
    assert {"--apps", "--accept", "--reject", "--reason", "--library", "--retries"} <= named
