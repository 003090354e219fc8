"""The last configuration mistakes of the audit, each a clear error (exit 2) at once: an endpoint that is
not an http(s) URL, an output path that cannot be a folder or a file, a run plan too large to list, and a
gate given no scenario.
"""

from __future__ import annotations

import json
import resource
import subprocess
import sys
import time
from pathlib import Path

import pytest

from pare.agents.models import ModelConfig
from pare.bench.runconfig import MAX_RUNS
from pare.cli import main
from pare.errors import UserInputError
from pare.results.run_folder import MANIFEST, MAX_PLANNED_EPISODES
from pare.testing import ChatServer, proactive_play

WANTED = "must be an http:// or https:// URL with a host"
NOT_URLS = ["notaurl", "ftp://models.example/v1", "http://[::1", "http:///v1", "localhost:8000/v1"]


def refused(capsys: pytest.CaptureFixture[str], argv: list[str]) -> str:
    """Run the command line; it must exit 2 at once, without a traceback; return its error, unwrapped."""
    started = time.perf_counter()
    code = main(argv)
    elapsed = time.perf_counter() - started
    err = capsys.readouterr().err
    assert code == 2, err
    assert "Traceback" not in err and err.startswith("error:")
    assert elapsed < 10, f"took {elapsed:.1f}s to refuse"
    return " ".join(err.split())


# -- endpoints ----------------------------------------------------------------------------------------------
@pytest.mark.parametrize("endpoint", NOT_URLS)
def test_an_endpoint_that_is_not_an_http_url_is_a_configuration_mistake_naming_the_role(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], endpoint: str
) -> None:
    with ChatServer(proactive_play()) as server:
        argv = ["run", "-o", str(tmp_path / "out"), "--no-progress", "-s", "dentist_moves_checkup"]
        argv += ["--user-model", "u", "--user-endpoint", server.base_url]
        argv += ["--assistant-model", "a", "--assistant-endpoint", endpoint]
        err = refused(capsys, argv)
        assert server.request_count == 0
    assert f"models.assistant.api_base: Value error, {WANTED}" in err
    assert "models.user.api_base" not in err
    assert not (tmp_path / "out").exists()

    err = refused(
        capsys, ["generate", "--apps", "email", "-o", str(tmp_path / "gen"), "--endpoint", endpoint]
    )
    assert "generator.api_base" in err
    assert not (tmp_path / "gen").exists()


@pytest.mark.parametrize("endpoint", NOT_URLS)
def test_model_config_refuses_the_endpoint_where_it_is_read(endpoint: str) -> None:
    with pytest.raises(
        UserInputError, match=r"models\.execute: api_base: .*(https:// URL|not a URL|no host)"
    ):
        ModelConfig.parse({"model": "m", "api_base": endpoint}, where="models.execute")


@pytest.mark.parametrize(
    "endpoint",
    ["http://localhost:8000/v1", "https://api.example.com/v1", "http://[::1]:8000/v1", "HTTPS://Example.COM"],
)
def test_http_and_https_endpoints_are_taken_as_written(endpoint: str) -> None:
    assert ModelConfig(model="m", api_base=endpoint).api_base == endpoint


def test_the_error_does_not_repeat_an_endpoint_that_may_hold_a_key() -> None:
    with pytest.raises(UserInputError) as refused_config:
        ModelConfig.parse({"model": "m", "api_base": "ftp://user:sk-secret@models.example/v1"})
    assert "sk-secret" not in str(refused_config.value)


# -- output paths -------------------------------------------------------------------------------------------
def _bad_paths(tmp_path: Path) -> dict[str, Path]:
    a_file = tmp_path / "a_file"
    a_file.write_text("not a folder\n", encoding="utf-8")
    paths = {"a file": a_file, "through a file": a_file / "sub"}
    if Path("/proc").is_dir():  # Linux: a folder where nothing can be made
        paths["under /proc"] = Path("/proc/pare-cannot-be-here")
    return paths


def _commands(target: Path, example_scenario: Path, tmp_path: Path) -> dict[str, list[str]]:
    run = ["run", "--scenario-path", str(example_scenario), "--runs", "1", "--no-progress"]
    return {
        "run": [*run, "-o", str(target)],
        "sweep": [
            "sweep",
            "-g",
            "seed=[0, 1]",
            "--set",
            f"scenarios.paths=[{example_scenario}]",
            "-o",
            str(target),
        ],
        "generate": ["generate", "--apps", "email", "-o", str(target), "--endpoint", "http://127.0.0.1:9/v1"],
        "schema": ["scenarios", "schema", "-o", str(target / "schema.json")],
    }


@pytest.mark.parametrize("command", ["run", "sweep", "generate", "schema"])
def test_an_output_path_that_cannot_be_a_folder_is_a_clear_error(
    tmp_path: Path, example_scenario: Path, capsys: pytest.CaptureFixture[str], command: str
) -> None:
    for name, target in _bad_paths(tmp_path).items():
        err = refused(capsys, _commands(target, example_scenario, tmp_path)[command])
        assert str(target) in err, name


def test_report_and_export_to_a_path_that_cannot_be_written_are_clear_errors(
    tmp_path: Path, example_scenario: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    run = tmp_path / "run"
    argv = ["run", "--scenario-path", str(example_scenario), "--runs", "1", "--no-progress", "-o", str(run)]
    assert main(argv) == 0
    capsys.readouterr()
    for name, target in _bad_paths(tmp_path).items():
        for output in (target / "report.txt", target / "report.md"):
            fmt = "markdown" if output.suffix == ".md" else "terminal"
            err = refused(capsys, ["report", str(run), "-f", fmt, "-o", str(output)])
            assert str(output) in err, name
        if name != "a file":  # an existing file is refused by the export itself
            pytest.importorskip("jinja2")
            err = refused(capsys, ["view", str(run), "--export", str(target)])
            assert str(target) in err, name
    assert "is a folder" in refused(capsys, ["report", str(run), "-o", str(tmp_path)])


# -- run plans ----------------------------------------------------------------------------------------------
MEMORY = 1024**3


def _limited() -> None:
    resource.setrlimit(resource.RLIMIT_AS, (MEMORY, MEMORY))


@pytest.mark.parametrize(
    ("runs", "scenarios", "expected"),
    [
        (10**8, 1, f"more than a run can have ({MAX_RUNS})"),
        (MAX_RUNS, MAX_PLANNED_EPISODES // MAX_RUNS + 1, f"more than the {MAX_PLANNED_EPISODES:,} episodes"),
    ],
    ids=["runs", "scenarios_times_runs"],
)
def test_a_damaged_plan_too_large_to_list_is_refused_by_the_report(
    tmp_path: Path, example_scenario: Path, runs: int, scenarios: int, expected: str
) -> None:
    run = tmp_path / "run"
    argv = ["run", "--scenario-path", str(example_scenario), "--runs", "1", "--no-progress", "-o", str(run)]
    assert main(argv) == 0
    manifest = json.loads((run / MANIFEST).read_text(encoding="utf-8"))
    manifest["plan"] = {"runs": runs, "scenarios": {f"s{index}": "0" for index in range(scenarios)}}
    (run / MANIFEST).write_text(json.dumps(manifest), encoding="utf-8")
    # In a child process with 1 GiB: a regression lists 10^8 episodes and fails there, not the machine.
    done = subprocess.run(
        [sys.executable, "-m", "pare", "report", str(run)],
        capture_output=True,
        text=True,
        timeout=60,
        check=False,
        preexec_fn=_limited,
    )
    assert done.returncode == 2, done.stderr[-2_000:]
    assert expected in " ".join(done.stderr.split()) and "damaged" in done.stderr


# -- the gate with nothing to check -------------------------------------------------------------------------
def test_checking_an_empty_folder_says_no_scenario_was_found(
    tmp_path: Path, example_scenario: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    empty = tmp_path / "empty"
    empty.mkdir()
    err = refused(capsys, ["scenarios", "check", str(empty)])
    assert "no scenario was found in" in err and str(empty) in err

    err = refused(capsys, ["scenarios", "check", str(example_scenario), "--tag", "goal_inference"])
    assert "matches the filters" in err
