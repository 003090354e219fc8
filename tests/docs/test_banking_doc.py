"""The Banking page (docs/banking.md) says what the app is: its diagram, its tools and their harm classes."""

from __future__ import annotations

import re
from decimal import Decimal
from pathlib import Path

from pare.apps.banking import BankingApp
from pare.apps.fsm import to_mermaid
from pare.scenarios.seed import prepare_seed
from pare.yaml_source import load_yaml
from tests.conftest import START, make_env

PAGE = Path(__file__).parents[2] / "docs" / "banking.md"


def _block(language: str) -> str:
    found = re.search(rf"```{language}\n(.*?)```", PAGE.read_text(encoding="utf-8"), re.S)
    assert found is not None
    return found.group(1)


def test_the_diagram_is_the_app_s() -> None:
    assert _block("mermaid") == to_mermaid(BankingApp)


def test_every_tool_is_listed_with_its_kind_and_harm() -> None:
    rows = [line for line in PAGE.read_text(encoding="utf-8").splitlines() if line.startswith("| `")]
    listed: dict[str, tuple[str, str]] = {}
    for row in rows:
        names, kind, harm = (cell.strip() for cell in row.strip("|").split("|"))
        for name in re.findall(r"`(\w+)`", names):
            listed[name] = (kind, harm)
    assert set(listed) == set(BankingApp.tools)
    for name, spec in BankingApp.tools.items():
        assert listed[name] == (spec.kind, BankingApp.harm.get(name, "")), name


def test_the_seed_example_loads() -> None:
    seed = load_yaml(_block("yaml"))["seed"]
    env = make_env(["banking"], {"banking": prepare_seed("banking", seed["banking"], START)[0]})
    assert env.apps["banking"].state.accounts["acc-main"].available == Decimal("2342.37")
