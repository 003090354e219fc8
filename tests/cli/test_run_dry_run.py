"""`pare run --dry-run` and the judge's flags and provenance: what a first model run shows before it runs.

Every model here is a local :class:`~pare.testing.ChatServer` on 127.0.0.1 that counts its requests, so
"calls nothing" is checked, not assumed.
"""

from __future__ import annotations

import json
import re
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

from pare.cli import main
from pare.results.run_folder import MANIFEST, load_run
from pare.testing import ChatServer, proactive_play

KEY_VARIABLE = "PARE_DRY_RUN_TEST_KEY"
KEY = "sk-pare-dry-run-KEY-51c0e7a2"  # recognisable, so a leak into the output is easy to find
SCENARIOS = ("dentist_moves_checkup", "five_a_side_kickoff_moved")
PRICES = {"input": 2.0, "output": 8.0}


@pytest.fixture(autouse=True)
def wide(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("COLUMNS", "200")


@pytest.fixture
def server() -> Iterator[ChatServer]:
    with ChatServer(proactive_play()) as chat:
        yield chat


def model_run(output: Path, server: ChatServer, *extra: str, runs: int = 2) -> list[str]:
    """A model run of the two scenarios, every role on ``server``, keys read from KEY_VARIABLE."""
    argv = ["run", "--output", str(output), "--no-progress", "--runs", str(runs)]
    for scenario in SCENARIOS:
        argv += ["-s", scenario]
    argv += ["--user-model", "small-user", "--user-endpoint", server.base_url]
    argv += ["--assistant-model", "big-assistant", "--assistant-endpoint", server.base_url]
    for role in ("user", "assistant"):
        argv += ["--set", f"models.{role}.api_key_env={KEY_VARIABLE}"]
        argv += ["--set", f"models.{role}.prices={{input: {PRICES['input']}, output: {PRICES['output']}}}"]
    return argv + list(extra)


def dry_json(argv: list[str], capsys: pytest.CaptureFixture[str]) -> dict[str, Any]:
    capsys.readouterr()
    assert main([*argv, "--dry-run", "--format", "json"]) == 0
    data: dict[str, Any] = json.loads(capsys.readouterr().out)
    return data


def test_dry_run_calls_nothing_makes_no_folder_and_shows_the_plan(
    tmp_path: Path, server: ChatServer, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    monkeypatch.setenv(KEY_VARIABLE, KEY)
    output = tmp_path / "run"
    assert main([*model_run(output, server, runs=3), "--dry-run"]) == 0
    out = capsys.readouterr().out
    assert server.request_count == 0
    assert not output.exists()
    for role, model in (("user", "small-user"), ("observe", "big-assistant"), ("execute", "big-assistant")):
        assert re.search(rf"^\s*{role}\s*│\s*{model}\s*│\s*openai\s*│\s*{server.base_url}", out, re.MULTILINE)
    assert f"{KEY_VARIABLE}: found" in out and KEY not in out
    assert "2 scenarios x 3 runs = 6; 0 already finished; 6 to run" in out
    assert "Estimate for the 6 episodes to run" in out
    assert "typical - upper bound" in out and "Tokens = characters / 4" in out
    # the judge was not set: it is the user's model, and the plan says so
    assert "judged by the user's model (small-user)" in out


def test_a_missing_key_is_reported_not_an_error(
    tmp_path: Path, server: ChatServer, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    monkeypatch.delenv(KEY_VARIABLE, raising=False)
    assert main([*model_run(tmp_path / "run", server), "--dry-run"]) == 0
    out = capsys.readouterr().out
    assert f"{KEY_VARIABLE}: missing (user, observe, execute, judge)" in out
    assert f"export {KEY_VARIABLE}=" in out
    assert server.request_count == 0
    # the real run refuses to start for the same reason
    assert main(model_run(tmp_path / "run", server)) == 2
    assert KEY_VARIABLE in capsys.readouterr().err


def test_the_estimate_is_a_range_priced_from_the_configuration(
    tmp_path: Path, server: ChatServer, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    monkeypatch.setenv(KEY_VARIABLE, KEY)
    plan = dry_json(model_run(tmp_path / "run", server, "--set", "models.assistant.max_tokens=300"), capsys)
    estimate = plan["estimate"]
    assert estimate["episodes"] == 4 and estimate["chars_per_token"] == 4.0
    roles = {role["role"]: role for role in estimate["roles"]}
    assert set(roles) == {"user", "observe", "execute", "judge"}
    for role in roles.values():
        for figure in ("calls", "prompt_tokens", "completion_tokens", "cost_usd"):
            assert 0 < role[figure]["typical"] <= role[figure]["upper"], (role["role"], figure)
        for bound in ("typical", "upper"):  # priced from the configuration's prices
            expected = (
                role["prompt_tokens"][bound] * PRICES["input"]
                + role["completion_tokens"][bound] * PRICES["output"]
            ) / 1e6
            assert role["cost_usd"][bound] == pytest.approx(expected, rel=1e-3, abs=1e-5)
    # answers in the upper bound are as long as max_tokens allows
    assert roles["observe"]["completion_tokens"]["upper"] == roles["observe"]["calls"]["upper"] * 300
    assert estimate["cost_usd"]["typical"] == pytest.approx(
        sum(r["cost_usd"]["typical"] for r in roles.values())
    )
    assert server.request_count == 0


def test_unknown_prices_are_unknown_not_zero(
    tmp_path: Path, server: ChatServer, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    monkeypatch.setenv(KEY_VARIABLE, KEY)
    argv = [*model_run(tmp_path / "run", server), "--set", "models.user.prices=null"]
    plan = dry_json(argv, capsys)
    roles = {role["role"]: role for role in plan["estimate"]["roles"]}
    assert roles["user"]["cost_usd"] is None and roles["judge"]["cost_usd"] is None
    assert roles["observe"]["cost_usd"] is not None
    assert plan["estimate"]["cost_usd"] is None
    assert main([*argv, "--dry-run"]) == 0
    out = capsys.readouterr().out
    total = next(line for line in out.splitlines() if line.strip().startswith("total"))
    assert total.rstrip().endswith("+ unknown") and "$" in total
    assert "No price for user, judge" in out


def test_the_dry_run_counts_what_the_folder_already_holds(
    tmp_path: Path, server: ChatServer, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    monkeypatch.setenv(KEY_VARIABLE, KEY)
    output = tmp_path / "run"
    assert main(model_run(output, server, runs=1)) == 0
    calls = server.request_count
    manifest = (output / MANIFEST).read_bytes()
    plan = dry_json(model_run(output, server, runs=3), capsys)
    assert plan["episodes"] | {"folder": None} == {
        "scenarios": 2,
        "runs": 3,
        "planned": 6,
        "finished": 2,
        "to_run": 4,
        "folder": None,
        "folder_exists": True,
        "refused": None,
    }
    assert plan["estimate"]["episodes"] == 4
    assert server.request_count == calls and (output / MANIFEST).read_bytes() == manifest
    # a folder of another configuration: the dry run says the run would refuse it
    plan = dry_json(model_run(output, server, "--max-turns", "7"), capsys)
    assert plan["episodes"]["refused"] and plan["episodes"]["to_run"] == 0


def test_an_oracle_dry_run_has_no_estimate(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    plan = dry_json(["run", "--split", "smoke", "--runs", "1", "-o", str(tmp_path / "run")], capsys)
    assert plan["estimate"] is None and plan["keys"] == []
    assert [role["model"] for role in plan["roles"]] == [None, None, None, None]
    assert plan["episodes"]["planned"] == 5
    assert not (tmp_path / "run").exists()


@pytest.mark.parametrize("role", ["user", "assistant", "observe", "execute", "judge"])
def test_every_role_has_its_model_provider_and_endpoint_flags(
    role: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    endpoint = f"https://{role}.example.test/v1"
    argv = ["run", "-s", SCENARIOS[0], "--runs", "1", "-o", str(tmp_path / "run")]
    if role in ("judge", "execute"):  # a judge needs models to judge; an execute model an observe model
        argv += ["--observe-model", "watcher"]
    argv += [
        f"--{role}-model",
        f"{role}-model",
        f"--{role}-provider",
        "litellm",
        f"--{role}-endpoint",
        endpoint,
    ]
    lines = {line["role"]: line for line in dry_json(argv, capsys)["roles"]}
    for resolved in ("observe", "execute") if role == "assistant" else (role,):
        line = lines[resolved]
        assert (line["model"], line["backend"], line["endpoint"]) == (f"{role}-model", "litellm", endpoint)


def test_the_manifest_and_the_output_say_who_judges(
    tmp_path: Path, server: ChatServer, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    monkeypatch.setenv(KEY_VARIABLE, KEY)
    inherited = tmp_path / "inherited"
    assert main(model_run(inherited, server, runs=1)) == 0
    out = capsys.readouterr().out
    assert out.count("judged by the user's model (small-user)") == 2  # before the run and after it
    judge = load_run(inherited).manifest["judge"]
    assert (judge["model"], judge["inherited_from"], judge["deterministic_fallback"]) == (
        "small-user",
        "user",
        False,
    )

    chosen = tmp_path / "chosen"
    argv = model_run(
        chosen, server, "--judge-model", "careful-judge", "--judge-endpoint", server.base_url, runs=1
    )
    argv += ["--set", f"models.judge.api_key_env={KEY_VARIABLE}"]
    assert main(argv) == 0
    assert "judged by the user's model" not in capsys.readouterr().out
    judge = load_run(chosen).manifest["judge"]
    assert (judge["model"], judge["endpoint"], judge["inherited_from"]) == (
        "careful-judge",
        server.base_url,
        None,
    )


def test_an_oracle_run_is_judged_by_the_fallbacks(tmp_path: Path) -> None:
    assert main(["run", "-s", SCENARIOS[0], "--runs", "1", "-o", str(tmp_path / "run"), "--no-progress"]) == 0
    assert load_run(tmp_path / "run").manifest["judge"] == {
        "model": None,
        "inherited_from": None,
        "deterministic_fallback": True,
    }


def test_format_belongs_to_the_dry_run(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["run", "--format", "json", "-o", str(tmp_path / "run")]) == 2
    assert "--dry-run" in capsys.readouterr().err
    assert main(["run", "--dry-run", "--format", "yaml", "-o", str(tmp_path / "run")]) == 2
    assert not (tmp_path / "run").exists()


def test_credentials_in_an_endpoint_or_extra_are_never_printed(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    endpoint = "https://me:hunter2@models.example.test/v1?api-key=abc123"
    argv = ["run", "-s", SCENARIOS[0], "--runs", "1", "-o", str(tmp_path / "run"), "--user-model", "u"]
    argv += ["--user-endpoint", endpoint, "--set", "models.user.prices={input: 1, output: 1}"]
    argv += ["--set", "models.user.extra={top_p: 0.9, extra_headers: {x-auth-token: tok-s3cr3t}}"]
    for output_format in ("text", "json"):
        capsys.readouterr()
        assert main([*argv, "--dry-run", "--format", output_format]) == 0
        out = capsys.readouterr().out
        assert "hunter2" not in out and "abc123" not in out and "models.example.test" in out
        assert "tok-s3cr3t" not in out and "top_p" in out  # what is sent is shown, secrets masked
