"""The scenario guide's worked example is a real scenario: it loads and passes the whole gate."""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path
from typing import Any

import pytest
import yaml

from pare.bench.selftest import check_scenario
from pare.cli import main
from pare.scenarios import parse_scenario
from pare.scenarios.kinds import matcher_problems
from pare.scenarios.matchers import OPERATORS, compile_matcher
from pare.scenarios.model import ActionPattern
from pare.scenarios.operator_docs import TABLE_END, TABLE_START
from pare.scenarios.schema import SCHEMA_FILE
from pare.yaml_source import load_yaml

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


def _inline_examples() -> list[tuple[str, dict[str, Any]]]:
    """The guide's inline examples of patterns, matchers and `where` conditions (``{...}`` in backquotes),
    but those with a placeholder (``...``, ``<Bob's email>``) or without values (``{min, max}``).
    """
    text = GUIDE.read_text(encoding="utf-8")
    found = []
    for written in re.findall(r"`([^`\n]*\{[^`\n]*)`", text):
        if "..." in written or "<" in written or "${" in written:
            continue
        data = yaml.safe_load(written)
        if isinstance(data, dict) and None not in data.values():
            found.append((written, data))
    return found


def _loads_as_a_check(check: dict[str, Any]) -> None:
    """Load the worked example with ``check`` added to its goal 'confirmed': through the whole loader."""
    data = load_yaml(_complete_example())
    data["goals"][1]["checks"].append(check)
    parse_scenario(yaml.safe_dump(data, sort_keys=False), source="docs/writing-scenarios.md")


PATTERN_FIELDS = set(ActionPattern.model_fields)


def test_every_inline_example_is_accepted_by_the_loader() -> None:
    examples = _inline_examples()
    assert len(examples) >= 10
    for written, data in examples:
        try:
            if set(data) <= PATTERN_FIELDS:  # a pattern: as an action check of the worked example
                _loads_as_a_check({"action": data})
            elif list(data) == ["where"]:  # a condition on items: on the example's calendar events
                _loads_as_a_check({"state": {"path": "calendar.events", **data}})
            elif list(data) == ["any_of"] and not any(set(item) & set(OPERATORS) for item in data["any_of"]):
                # alternatives of fields in a `where`
                _loads_as_a_check({"state": {"path": "calendar.events", "where": data}})
            elif len(data) == 1:  # `field: matcher`
                (matcher,) = data.values()
                compile_matcher(matcher)
                assert not list(matcher_problems(matcher, Any)), written
            else:  # a bare matcher
                compile_matcher(data)
        except Exception as error:  # name the example that broke
            raise AssertionError(f"{written}: {error}") from error


def test_the_either_a_reply_or_a_new_email_pattern_is_given_whole() -> None:
    patterns = [data for _, data in _inline_examples() if "email__reply_to_email" in str(data.get("tool"))]
    assert any("any_of" in str(pattern["args"]) for pattern in patterns)
    assert "an `any_of` of patterns" not in GUIDE.read_text(encoding="utf-8")


def test_the_operator_table_is_the_one_the_operators_records_make() -> None:
    script = Path(__file__).parents[2] / "scripts" / "operator_table.py"
    done = subprocess.run(
        [sys.executable, str(script), "--check"], capture_output=True, text=True, check=False
    )
    assert done.returncode == 0, done.stdout + done.stderr
    table = GUIDE.read_text(encoding="utf-8").split(TABLE_START)[1].split(TABLE_END)[0]
    assert re.findall(r"^\| `(\w+)` \|", table, re.M) == list(OPERATORS)


def test_the_operator_table_check_fails_on_a_stale_table(tmp_path: Path) -> None:
    stale = tmp_path / "guide.md"
    stale.write_text(
        GUIDE.read_text(encoding="utf-8").replace("| `regex` |", "| `regexp` |"), encoding="utf-8"
    )
    script = Path(__file__).parents[2] / "scripts" / "operator_table.py"
    command = [sys.executable, str(script), "--guide", str(stale)]
    assert subprocess.run([*command, "--check"], capture_output=True, check=False).returncode == 1
    assert subprocess.run(command, capture_output=True, check=False).returncode == 0
    assert stale.read_text(encoding="utf-8") == GUIDE.read_text(encoding="utf-8")
