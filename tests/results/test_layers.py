"""Results are read without the package that runs models: reports, figures and the viewer must open a run
folder on an install (or in a process) where nothing of :mod:`pare.bench` or a provider SDK is loaded."""

from __future__ import annotations

import json
import subprocess
import sys

READERS = (
    "pare.results",
    "pare.results.trajectory",
    "pare.results.records",
    "pare.results.run_folder",
    "pare.results.metrics",
    "pare.results.report",
    "pare.results.plots",
    "pare.viewer",
    "pare.cli.report_cmd",
)
FORBIDDEN = ("pare.bench", "openai", "litellm", "ray")


def test_reading_results_loads_nothing_that_runs_models() -> None:
    program = (
        "import importlib, json, sys\n"
        f"for name in {READERS!r}: importlib.import_module(name)\n"
        f"print(json.dumps(sorted(m for m in sys.modules if m.split('.')[0] in {FORBIDDEN[1:]!r} "
        f"or m == 'pare.bench' or m.startswith('pare.bench.'))))\n"
    )
    done = subprocess.run([sys.executable, "-c", program], capture_output=True, text=True, check=True)
    assert json.loads(done.stdout) == []
