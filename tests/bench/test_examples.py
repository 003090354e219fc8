"""The example configurations in examples/ stay valid."""

from __future__ import annotations

from pathlib import Path

import pytest

from pare.bench.runconfig import build_config, read_config_file
from pare.bench.sweep import load_sweep, point_configs

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


@pytest.mark.parametrize("path", sorted(EXAMPLES.glob("run-*.yaml")), ids=lambda p: p.name)
def test_run_examples_are_valid(path: Path) -> None:
    config = build_config(read_config_file(path), source=str(path))
    assert not config.oracle_only


@pytest.mark.parametrize("path", sorted(EXAMPLES.glob("sweep-*.yaml")), ids=lambda p: p.name)
def test_sweep_examples_are_valid(path: Path) -> None:
    spec, base = load_sweep(path)
    configs = point_configs(spec, base)
    assert len(configs) > 1
    assert len({config.identity_hash() for _, config in configs}) == len(configs)
