"""The gate plays a scenario's runs in one event loop and keeps each episode's result."""

from __future__ import annotations

import pytest

from pare.bench.episode import EpisodeResult
from pare.bench.selftest import check_scenario
from tests.scenarios.helpers import fair, parse


def test_the_gate_keeps_every_result_without_formatting_it(monkeypatch: pytest.MonkeyPatch) -> None:
    """asyncio formats what a run returns when it puts the Ctrl-C handler back (quietly: a failing
    repr is swallowed); the gate hands its episodes back another way, since formatting one costs more
    than playing it."""
    formatted: list[str] = []

    def counted(self: EpisodeResult) -> str:
        formatted.append(self.scenario_id)
        return "<episode>"

    monkeypatch.setattr(EpisodeResult, "__repr__", counted)
    verdict = check_scenario(parse(fair()))
    assert verdict.ok, verdict.breaches()
    assert set(verdict.details) == {run.run for run in verdict.runs}
    assert formatted == []
