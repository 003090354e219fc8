"""Any agent in ``pare run``: policies named by built-in name or ``MODULE:FACTORY``, end to end."""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest

from pare.bench.policies import PolicyContext, build, resolve
from pare.bench.runconfig import build_config
from pare.cli import main
from pare.errors import UserInputError
from pare.results.run_folder import load_run
from pare.scenarios.library import get_scenario
from pare.scenarios.oracle import OracleAssistant
from pare.testing import ChatServer, completion
from pare.viewer import Catalog, Site
from tests.bench import custom_policies

DENTIST = "dentist_moves_checkup"
MODULE = "tests.bench.custom_policies"


@pytest.fixture(autouse=True)
def wide(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("COLUMNS", "240")


def run(output: Path, *extra: str, runs: int = 2) -> int:
    return main(["run", "-s", DENTIST, "--runs", str(runs), "--no-progress", "--output", str(output), *extra])


# -- names ------------------------------------------------------------------------------------------------
def test_a_misspelt_built_in_name_is_refused_with_a_suggestion(capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(UserInputError, match=r"unknown assistant policy 'orcale'\. Did you mean 'oracle'\?"):
        build_config({"policies": {"assistant": "orcale"}})
    assert main(["run", "--user-policy", "slwo", "--dry-run"]) == 2
    assert "Did you mean 'slow'?" in capsys.readouterr().err


def test_an_import_path_must_be_module_colon_factory() -> None:
    with pytest.raises(UserInputError, match="not an import path MODULE:FACTORY"):
        build_config({"policies": {"assistant": "my agents:make"}})


def test_a_module_that_is_not_there_is_named(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert run(tmp_path / "run", "--assistant-policy", "no_such_agents:make") == 2
    assert "no module named 'no_such_agents'" in capsys.readouterr().err
    assert not (tmp_path / "run").exists()  # refused before the folder is made


def test_a_missing_factory_gets_a_suggestion() -> None:
    with pytest.raises(
        UserInputError, match=r"has no attribute 'dentist_asistant'\. Did you mean 'dentist_assistant'"
    ):
        resolve("assistant", f"{MODULE}:dentist_asistant")


def test_a_factory_must_be_callable() -> None:
    with pytest.raises(UserInputError, match="is a int, not a factory"):
        resolve("assistant", f"{MODULE}:NOT_CALLABLE")


def test_a_module_that_fails_to_import_says_why(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    (tmp_path / "broken_agents.py").write_text("raise RuntimeError('half written')\n", encoding="utf-8")
    monkeypatch.syspath_prepend(str(tmp_path))
    with pytest.raises(UserInputError, match="importing 'broken_agents' failed: RuntimeError: half written"):
        resolve("assistant", "broken_agents:make")


def test_a_factory_that_returns_no_policy_stops_the_run(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    assert run(tmp_path / "run", "--assistant-policy", f"{MODULE}:not_a_policy") == 2
    error = capsys.readouterr().err
    assert f"'{MODULE}:not_a_policy' returned a builtins.str, not a pare.agents.AssistantPolicy" in error


def test_a_class_taking_the_context_is_a_factory() -> None:
    scenario = get_scenario(DENTIST)
    context = PolicyContext(role="assistant", scenario=scenario, run=1, seed=7)
    assert isinstance(build("assistant", "oracle", context), OracleAssistant)
    with pytest.raises(UserInputError, match="needs the 'observe' model, but none is configured"):
        build("assistant", f"{MODULE}:ModelProposer", context)


# -- policies and models ----------------------------------------------------------------------------------
def test_built_in_policies_must_fit_the_configured_models() -> None:
    with pytest.raises(UserInputError, match=r"policies\.assistant is 'model', but no assistant model"):
        build_config({"policies": {"assistant": "model"}})
    with pytest.raises(UserInputError, match=r"'oracle', which plays without a model, but models\.observe"):
        build_config({"policies": {"assistant": "oracle"}, "models": {"assistant": {"model": "gpt-4o"}}})
    with pytest.raises(
        UserInputError, match=r"'deterministic', which plays without a model, but models\.judge"
    ):
        build_config({"policies": {"judge": "deterministic"}, "models": {"judge": {"model": "gpt-4o"}}})


def test_a_deterministic_judge_does_not_take_the_users_model() -> None:
    config = build_config(
        {"policies": {"judge": "deterministic"}, "models": {"user": {"model": "gpt-5-mini"}}}
    )
    assert config.models.judge is None
    assert config.judge_provenance()["deterministic_fallback"] is True
    assert config.policy_names() == {"user": "model", "assistant": "oracle", "judge": "deterministic"}


def test_naming_the_default_policy_keeps_the_configuration() -> None:
    plain = build_config({})
    named = build_config({"policies": {"user": "oracle", "assistant": "oracle", "judge": "deterministic"}})
    assert named.identity() == plain.identity() and named.label() == plain.label() == "oracle"
    with_model = build_config(
        {"models": {"assistant": {"model": "gpt-4o"}}, "policies": {"assistant": "model"}}
    )
    assert (
        with_model.identity_hash()
        == build_config({"models": {"assistant": {"model": "gpt-4o"}}}).identity_hash()
    )


def test_a_policy_is_part_of_the_identity_and_the_label() -> None:
    custom = build_config({"policies": {"assistant": f"{MODULE}:dentist_assistant", "user": "slow"}})
    assert custom.identity()["policies"] == {"assistant": f"{MODULE}:dentist_assistant", "user": "slow"}
    assert custom.identity_hash() != build_config({}).identity_hash()
    assert custom.label() == f"{MODULE}:dentist_assistant (user slow)"
    with_model = build_config(
        {"policies": {"assistant": f"{MODULE}:ModelProposer"}, "models": {"assistant": {"model": "m"}}}
    )
    assert with_model.label() == f"{MODULE}:ModelProposer[m]"


# -- end to end -------------------------------------------------------------------------------------------
def test_a_custom_assistant_runs_through_pare_run_report_and_view(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    name = f"{MODULE}:dentist_assistant"
    custom_policies.CREATED.clear()
    assert run(tmp_path / "run", "--assistant-policy", name) == 0
    assert f"assistant {name}" in capsys.readouterr().out

    loaded = load_run(tmp_path / "run")
    assert loaded.label == name
    assert loaded.manifest["policies"] == {"user": "oracle", "assistant": name, "judge": "deterministic"}
    assert [record.success for record in loaded.records] == [True, True]
    contexts = sorted(custom_policies.CREATED, key=lambda context: context.run)
    config = build_config({"policies": {"assistant": name}})
    assert [(c.role, c.scenario.id, c.run, c.seed) for c in contexts] == [
        ("assistant", DENTIST, run_index, config.episode_seed(DENTIST, run_index)) for run_index in (1, 2)
    ]
    assert all(not context.models for context in contexts)

    assert main(["report", str(tmp_path / "run"), "--format", "json"]) == 0
    [reported] = json.loads(capsys.readouterr().out)["configurations"]
    assert reported["label"] == name and reported["success_rate"]["mean"] == 1.0

    site = Site(Catalog.open([tmp_path / "run"]))
    page = site.page("c/run/index.html")
    assert page is not None
    text = page.body.decode()
    assert f"assistant {name}" in text and "user oracle" in text
    episode = site.page(f"c/run/e/{DENTIST}/run-1.html")
    assert episode is not None and name in episode.body.decode()

    # the same command resumes; another assistant in the same folder is refused, the policy named
    assert run(tmp_path / "run", "--assistant-policy", name) == 0
    capsys.readouterr()
    assert run(tmp_path / "run", "--assistant-policy", "silent") == 2
    assert "policies.assistant" in capsys.readouterr().err


def test_a_custom_user_plays_against_the_oracle(tmp_path: Path) -> None:
    assert run(tmp_path / "run", "--user-policy", f"{MODULE}:waiting_user", runs=1) == 0
    loaded = load_run(tmp_path / "run")
    assert loaded.label == f"oracle (user {MODULE}:waiting_user)"
    [record] = loaded.records
    assert record.complete and not record.success  # the proposal is never accepted


def test_a_custom_judge_reads_the_free_text_checks(tmp_path: Path) -> None:
    vague = f"{MODULE}:vague_dentist_assistant"
    assert run(tmp_path / "fallback", "--assistant-policy", vague, runs=1) == 0
    assert [r.success for r in load_run(tmp_path / "fallback").records] == [False]
    judged = ["--set", f"policies.judge={MODULE}:always_yes"]
    assert run(tmp_path / "judged", "--assistant-policy", vague, *judged, runs=1) == 0
    loaded = load_run(tmp_path / "judged")
    assert [r.success for r in loaded.records] == [True]
    assert loaded.manifest["judge"]["policy"] == f"{MODULE}:always_yes"
    assert loaded.manifest["judge"]["deterministic_fallback"] is False


def test_a_custom_assistant_calls_the_configured_model_through_the_run(tmp_path: Path) -> None:
    with ChatServer(lambda body: completion("Shall I tidy your inbox?", prompt_tokens=30)) as server:
        argv = ["--assistant-policy", f"{MODULE}:ModelProposer", "--assistant-model", "tiny"]
        argv += ["--assistant-endpoint", server.base_url, "--set", "models.assistant.api_key_env=null"]
        assert run(tmp_path / "run", *argv, runs=1) == 0
        assert server.request_count == 1
    [record] = load_run(tmp_path / "run").records
    assert record.complete and record.usage["observe"].calls == 1
    assert record.usage["observe"].prompt_tokens == 30


def test_the_dry_run_says_who_plays_each_role(capsys: pytest.CaptureFixture[str]) -> None:
    argv = ["run", "-s", DENTIST, "--dry-run", "--format", "json", "--user-policy", "busy"]
    assert main([*argv, "--assistant-policy", f"{MODULE}:dentist_assistant"]) == 0
    plan = json.loads(capsys.readouterr().out)
    assert {line["role"]: line["policy"] for line in plan["roles"]} == {
        "user": "busy",
        "observe": f"{MODULE}:dentist_assistant",
        "execute": f"{MODULE}:dentist_assistant",
        "judge": "deterministic",
    }
    assert main([*argv, "--assistant-policy", f"{MODULE}:no_such_factory"]) == 2


def test_a_policy_that_raises_fails_its_episode_and_plays_again_on_resume(tmp_path: Path) -> None:
    assert run(tmp_path / "run", "--assistant-policy", f"{MODULE}:crashing", runs=1) == 1
    [record] = load_run(tmp_path / "run").records
    assert record.failure is not None and record.failure.kind == "internal_error"
    assert "my scaffold broke" in record.failure.message
    assert run(tmp_path / "run", "--assistant-policy", f"{MODULE}:crashing", runs=1) == 1
    lines = (tmp_path / "run" / "episodes.jsonl").read_text(encoding="utf-8").splitlines()
    assert len(lines) == 2  # played again on resume, not skipped as finished


DOCS = Path(__file__).resolve().parents[2] / "docs" / "running-benchmarks.md"


def test_the_documented_assistant_runs(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    blocks = re.findall(r"```python\n(.*?)```", DOCS.read_text(encoding="utf-8"), re.S)
    (module,) = [block for block in blocks if block.startswith("# my_agents.py")]
    (tmp_path / "docs_agents.py").write_text(module, encoding="utf-8")
    monkeypatch.syspath_prepend(str(tmp_path))
    assert run(tmp_path / "run", "--assistant-policy", "docs_agents:make", runs=1) == 0
    [record] = load_run(tmp_path / "run").records
    assert record.complete and [p.decision for p in record.proposals] == ["accept"]
    assert record.read_actions == 1
