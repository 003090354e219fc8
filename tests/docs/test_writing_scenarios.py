"""The scenario guide's worked example is a real scenario: it loads and passes the whole gate."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from pare.bench.selftest import check_scenario
from pare.cli import main
from pare.scenarios import parse_scenario
from pare.scenarios.schema import SCHEMA_FILE

GUIDE = Path(__file__).parents[2] / "docs" / "writing-scenarios.md"


def _complete_example() -> str:
    text = GUIDE.read_text(encoding="utf-8")
    section = text[text.index("## A complete example") :]
    found = re.search(r"```yaml\n(.*?)```", section, re.S)
    assert found is not None
    return found.group(1)


def test_the_worked_example_passes_the_gate() -> None:
    scenario = parse_scenario(_complete_example(), source="docs/writing-scenarios.md")
    verdict = check_scenario(scenario)
    assert verdict.ok, verdict.breaches()
    assert not verdict.warnings
    declared = {variant.id: variant.expect for variant in scenario.variants}
    assert sorted(declared.values()) == ["fail", "fail", "fail", "pass"]


def test_the_guides_relative_links_resolve() -> None:
    text = GUIDE.read_text(encoding="utf-8")
    for target in re.findall(r"\]\(([^)#]+)\)", text):
        if "://" not in target:
            assert (GUIDE.parent / target).exists(), target


def test_schema_path_is_the_installed_schema(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["scenarios", "schema", "--path"]) == 0
    assert Path(capsys.readouterr().out.strip()) == SCHEMA_FILE.resolve()
