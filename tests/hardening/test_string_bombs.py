"""One long string named by many aliases: a small file whose data is gigabytes once expanded. Every place
PARE reads YAML refuses it by its expanded size, with a clear error, before anything copies the data.

The files are small (at most a few hundred KB) but expand to a gigabyte or more: the command-line tests
run in a child process limited to 1 GiB of memory, so a regression fails the test instead of the machine.
"""

from __future__ import annotations

import json
import resource
import subprocess
import sys
from pathlib import Path

import pytest

from pare.cli import main
from pare.generate.folder import OUTCOMES
from pare.scenarios.loader import ScenarioError, parse_scenario
from pare.testing import ChatServer
from pare.yaml_source import MAX_EXPANDED_CHARS, YamlSyntaxError, load_yaml, parse_yaml
from tests.generate.conftest import ScriptedGenerator, example_answers, library

__all__ = ["library"]

MEMORY = 1024**3
"""The memory a child process may take: a regression expands a bomb past it and dies, the test fails."""
LIMIT = f"{MAX_EXPANDED_CHARS:,} characters"


def _bomb_list(string: int, aliases: int, indent: str = "") -> str:
    """A mapping with one ``string``-character value named by ``aliases`` aliases in a flow list."""
    return f"{indent}long: &s {'x' * string}\n{indent}many: [{', '.join(['*s'] * aliases)}]\n"


def _limited() -> None:
    resource.setrlimit(resource.RLIMIT_AS, (MEMORY, MEMORY))


def pare_limited(*argv: str, timeout: float = 60) -> subprocess.CompletedProcess[str]:
    """``pare argv`` in a child process with at most :data:`MEMORY` of address space."""
    return subprocess.run(
        [sys.executable, "-m", "pare", *argv],
        capture_output=True,
        text=True,
        timeout=timeout,
        check=False,
        preexec_fn=_limited,
    )


def test_the_expanded_size_is_bounded_not_only_the_number_of_values() -> None:
    text = _bomb_list(100_000, 1_000)  # 100 KB of text, 100 million characters once expanded
    with pytest.raises(YamlSyntaxError, match=f"more than {LIMIT}") as refused:
        parse_yaml(text)
    assert refused.value.line == 2  # the list that holds the aliases
    with pytest.raises(YamlSyntaxError, match=f"more than {LIMIT}"):
        load_yaml(text)


def test_keys_count_as_text_and_repeating_text_within_the_bound_is_fine() -> None:
    long_key = "base: &s\n  ? " + "k" * 100_000 + "\n  : 1\n"  # an explicit key: implicit ones are short
    keyed = long_key + "many: [" + ", ".join(["*s"] * 1_000) + "]\n"
    with pytest.raises(YamlSyntaxError, match=f"more than {LIMIT}"):
        load_yaml(keyed)
    # A signature written once and named in twenty messages is what aliases are for.
    data = load_yaml(_bomb_list(1_000, 20))
    assert len(data["many"]) == 20 and data["many"][0] == "x" * 1_000


def test_a_merge_key_that_repeats_a_long_mapping_counts_each_time() -> None:
    mappings = "\n".join(f"  - {{<<: *base, n: {n}}}" for n in range(200))
    text = f"base: &base {{text: {'y' * 50_000}}}\nitems:\n{mappings}\n"
    with pytest.raises(YamlSyntaxError, match=f"more than {LIMIT}"):
        load_yaml(text)


def test_a_scenario_file_is_refused_with_its_file_and_line(tmp_path: Path) -> None:
    path = tmp_path / "bomb.yaml"
    path.write_text("id: bomb\ntitle: t\n" + _bomb_list(300_000, 10_000).replace("long:", "story:"))
    done = pare_limited("scenarios", "check", str(path))
    assert done.returncode == 2, done.stderr[-2_000:]
    err = " ".join(done.stderr.split())
    assert f"{path}:4" in err and LIMIT in err
    assert "Traceback" not in done.stderr


def test_a_run_configuration_is_refused_before_anything_is_done(tmp_path: Path) -> None:
    # The audit's file: 3.6 MB with a 3 MB string named 190,000 times; this one is 140 KB, 1 GB expanded.
    config = tmp_path / "run.yaml"
    head = "models:\n  assistant:\n    model: m\n    extra:\n"
    config.write_text(head + _bomb_list(100_000, 10_000, "      "))
    done = pare_limited("run", "-c", str(config), "-o", str(tmp_path / "out"), "--dry-run")
    assert done.returncode == 2, done.stderr[-2_000:]
    assert f"{config}:6" in done.stderr and LIMIT in " ".join(done.stderr.split())
    assert not (tmp_path / "out").exists()


def test_a_set_value_is_refused(tmp_path: Path) -> None:
    value = "{long: &s " + "x" * 60_000 + ", many: [" + ",".join(["*s"] * 15_000) + "]}"  # 120 KB
    setting = f"models.assistant.extra={value}"
    done = pare_limited("run", "--set", setting, "-o", str(tmp_path / "o"), "--dry-run")
    assert done.returncode == 2, done.stderr[-2_000:]
    assert "--set" in done.stderr and LIMIT in " ".join(done.stderr.split())


def test_a_bomb_in_a_generated_candidate_is_a_problem_for_the_generator() -> None:
    with pytest.raises(ScenarioError, match=LIMIT):
        parse_scenario("id: bomb\n" + _bomb_list(100_000, 1_000).replace("long:", "story:"))


def test_a_generator_that_answers_a_bomb_fails_that_candidate_and_the_batch_goes_on(
    tmp_path: Path, library: Path
) -> None:
    answers = example_answers()
    title = "title: The dentist moves tomorrow's check-up"
    tags = "tags: [context_observation, multi_app_orchestration]"
    assert title in answers["story"] and tags in answers["story"]
    # 100 million characters once expanded, in an answer short enough to pass the answer cap
    bomb = answers["story"].replace(title, f"title: &s {'z' * 20_000}")
    bomb = bomb.replace(tags, "tags: [" + ", ".join(["*s"] * 5_000) + "]")
    scripts = {1: {**{stage: [text] for stage, text in answers.items()}, "story": [bomb]}}
    folder = tmp_path / "out"
    argv = ["generate", "--apps", "email,calendar", "-n", "1", "-o", str(folder), "--no-progress"]
    argv += ["--library", str(library), "--model", "pare-generator", "--retries", "0"]
    with ChatServer(ScriptedGenerator(scripts)) as server:
        for _session in range(2):  # the second session resumes the same folder
            done = pare_limited(*argv, "--endpoint", server.base_url, timeout=120)
            assert done.returncode == 0, done.stderr[-2_000:]
    outcome = json.loads((folder / OUTCOMES).read_text(encoding="utf-8"))
    assert outcome["status"] == "failed" and outcome["stage"] == "story"
    assert any(LIMIT in problem for problem in outcome["problems"]), outcome["problems"]
    assert not list(folder.glob("*.yaml"))


def test_main_refuses_a_set_bomb_in_process(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    # The same refusal through the in-process entry point tests use (no expansion happens before it).
    value = "[&s " + "x" * 100_000 + ", " + ", ".join(["*s"] * 1_000) + "]"
    assert main(["run", "--set", f"models.assistant.extra.k={value}", "-o", str(tmp_path / "o")]) == 2
    assert LIMIT in " ".join(capsys.readouterr().err.split())
