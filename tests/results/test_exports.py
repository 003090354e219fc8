"""``pare export`` of runs: the Every Eval Ever files validated against that project's JSON schemas
(vendored in eee_schema/, see its SOURCE.md), and the chat-format conversations for fine-tuning.
"""

from __future__ import annotations

import hashlib
import json
import os
import shutil
from pathlib import Path
from typing import Any

import jsonschema
import pytest

from pare.cli import main
from pare.results.metrics import compute_metrics
from pare.results.run_folder import load_run
from pare.results.trajectory import read_trajectory
from tests.viewer.runs import KEY_VARIABLE, Runs, make_runs

SCHEMAS = Path(__file__).parent / "eee_schema"


@pytest.fixture(scope="module")
def runs(tmp_path_factory: pytest.TempPathFactory) -> Runs:
    """The oracle (every episode succeeds) and scripted models (every episode fails), two runs each."""
    os.environ.setdefault(KEY_VARIABLE, "not-a-real-key")
    return make_runs(tmp_path_factory.mktemp("runs"))


def _schema(name: str) -> jsonschema.Draft7Validator:
    return jsonschema.Draft7Validator(json.loads((SCHEMAS / name).read_text(encoding="utf-8")))


def _export_eee(run: Path, out: Path) -> tuple[dict[str, Any], list[dict[str, Any]], Path]:
    assert main(["export", str(run), "--format", "eee", "-o", str(out), "--organization", "PARE tests"]) == 0
    (aggregate_file,) = [f for f in out.rglob("*.json")]
    aggregate = json.loads(aggregate_file.read_text(encoding="utf-8"))
    samples = out / aggregate["detailed_evaluation_results"]["file_path"]
    lines = [json.loads(line) for line in samples.read_text(encoding="utf-8").splitlines()]
    return aggregate, lines, samples


@pytest.mark.parametrize("which", ["oracle", "models"])
def test_eee_export_is_valid_against_the_schemas(runs: Runs, tmp_path: Path, which: str) -> None:
    aggregate, instances, samples = _export_eee(getattr(runs, which), tmp_path)
    _schema("eval.schema.json").validate(aggregate)
    validator = _schema("instance_level_eval.schema.json")
    for instance in instances:
        validator.validate(instance)
    details = aggregate["detailed_evaluation_results"]
    assert details["total_rows"] == len(instances) == 4
    assert details["checksum"] == hashlib.sha256(samples.read_bytes()).hexdigest()
    assert {instance["evaluation_id"] for instance in instances} == {aggregate["evaluation_id"]}
    assert {instance["model_id"] for instance in instances} == {aggregate["model_info"]["id"]}


def test_eee_aggregate_carries_the_metrics_with_their_uncertainty(runs: Runs, tmp_path: Path) -> None:
    aggregate, _, _ = _export_eee(runs.oracle, tmp_path)
    loaded = load_run(runs.oracle)
    metrics = compute_metrics(loaded.records, label=loaded.label, runs=loaded.runs, planned=loaded.planned)
    results = {result["evaluation_result_id"]: result for result in aggregate["evaluation_results"]}
    success = results["pare.success_rate"]["score_details"]
    assert success["score"] == metrics.success_rate.mean == 1.0
    interval = success["uncertainty"]["confidence_interval"]
    assert (interval["lower"], interval["upper"]) == metrics.success_rate_ci
    assert success["uncertainty"]["standard_error"]["value"] == metrics.success_rate.se
    assert results["pare.pass_hat_2"]["metric_config"]["metric_parameters"] == {"k": 2}
    assert results["pare.side_effect_rate"]["metric_config"]["lower_is_better"] is True
    assert aggregate["model_info"]["id"] == "pare/oracle"
    assert aggregate["source_metadata"]["source_organization_name"] == "PARE tests"


def test_eee_instances_hold_the_messages_and_the_tokens_per_role(runs: Runs, tmp_path: Path) -> None:
    _, instances, _ = _export_eee(runs.models, tmp_path)
    loaded = load_run(runs.models)
    record = next(r for r in loaded.records if (r.scenario_id, r.run) == ("dentist_moves_checkup", 1))
    instance = next(
        i for i in instances if i["sample_id"] == "dentist_moves_checkup" and i["metadata"]["run"] == "1"
    )
    assert record.trajectory is not None
    trajectory = read_trajectory(loaded.path / record.trajectory)
    written = [m["content"] for m in instance["messages"] if m["role"] in ("user", "assistant")]
    assert written == [step.action.raw for step in trajectory.steps]
    assert instance["evaluation"] == {
        "score": 0.0,
        "is_correct": False,
        "num_turns": record.turns,
        "tool_calls_count": len(trajectory.steps),
    }
    usage = instance["token_usage"]
    assert usage["input_tokens"] == sum(u.prompt_tokens for u in record.usage.values())
    assert usage["output_tokens"] == sum(u.completion_tokens for u in record.usage.values())
    for role, role_usage in record.usage.items():
        assert instance["metadata"][f"tokens.{role}.input"] == str(role_usage.prompt_tokens)


def _export_inspect(run: Path, out: Path) -> dict[str, Any]:
    assert main(["export", str(run), "--format", "inspect", "-o", str(out)]) == 0
    (log_file,) = list(out.glob("*.json"))
    log: dict[str, Any] = json.loads(log_file.read_text(encoding="utf-8"))
    return log


@pytest.mark.parametrize("which", ["oracle", "models"])
def test_inspect_log_is_valid_against_inspects_log_schema(runs: Runs, tmp_path: Path, which: str) -> None:
    log = _export_inspect(getattr(runs, which), tmp_path)
    schema = json.loads((Path(__file__).parent / "inspect_schema" / "eval_log.schema.json").read_text())
    jsonschema.Draft202012Validator(schema).validate(log)
    assert log["status"] == "success"
    assert sorted((s["id"], s["epoch"]) for s in log["samples"]) == [
        ("dentist_moves_checkup", 1),
        ("dentist_moves_checkup", 2),
        ("five_a_side_kickoff_moved", 1),
        ("five_a_side_kickoff_moved", 2),
    ]


def test_inspect_log_scores_each_episode_and_counts_tokens_per_role(runs: Runs, tmp_path: Path) -> None:
    log = _export_inspect(runs.models, tmp_path)
    loaded = load_run(runs.models)
    metrics = compute_metrics(loaded.records, label=loaded.label, runs=loaded.runs, planned=loaded.planned)
    (score,) = log["results"]["scores"]
    assert score["metrics"]["accuracy"]["value"] == metrics.success_rate.mean == 0.0
    assert {s["scores"]["pare_checks"]["value"] for s in log["samples"]} == {"I"}
    user_tokens = sum(r.usage["user"].prompt_tokens for r in loaded.records)
    assert log["stats"]["role_usage"]["user"]["input_tokens"] == user_tokens
    assert log["eval"]["model"] == "test-assistant"
    sample = next(s for s in log["samples"] if (s["id"], s["epoch"]) == ("dentist_moves_checkup", 1))
    record = next(r for r in loaded.records if r.key == ("dentist_moves_checkup", 1))
    assert record.trajectory is not None
    trajectory = read_trajectory(loaded.path / record.trajectory)
    assistant = [m for m in sample["messages"] if m["role"] == "assistant"]
    steps = [step for step in trajectory.steps if step.actor == "assistant"]
    assert [m["content"] for m in assistant] == [step.action.raw for step in steps]
    assert [m["tool_calls"][0]["function"] for m in assistant] == [step.action.tool for step in steps]


def _conversations(file: Path) -> list[dict[str, Any]]:
    return [json.loads(line) for line in file.read_text(encoding="utf-8").splitlines()]


def test_sft_writes_only_successful_episodes_by_default(runs: Runs, tmp_path: Path) -> None:
    out = tmp_path / "sft.jsonl"
    assert main(["export", str(runs.models), "--format", "sft", "-o", str(out)]) == 0
    assert _conversations(out) == []  # every episode of the scripted models failed
    assert main(["export", str(runs.oracle), "--format", "sft", "-o", str(out)]) == 0
    assert _conversations(out) == []  # the oracle wrote nothing a model could learn from


def test_sft_conversations_are_the_models_own_answers_per_role(runs: Runs, tmp_path: Path) -> None:
    # one episode of the models' run judged a success: only its conversations are written
    run = tmp_path / "run"
    shutil.copytree(runs.models, run)
    episodes = run / "episodes.jsonl"
    lines = [json.loads(line) for line in episodes.read_text(encoding="utf-8").splitlines()]
    for line in lines:
        if (line["scenario_id"], line["run"]) == ("dentist_moves_checkup", 2):
            line["success"] = True
    episodes.write_text("".join(json.dumps(line) + "\n" for line in lines), encoding="utf-8")
    out = tmp_path / "sft.jsonl"
    assert main(["export", str(run), "--format", "sft", "-o", str(out)]) == 0
    conversations = _conversations(out)
    assert {(c["scenario_id"], c["run"]) for c in conversations} == {("dentist_moves_checkup", 2)}
    assert {c["role"] for c in conversations} == {"user", "observe", "execute"}
    trajectory = read_trajectory(run / "trajectories" / "dentist_moves_checkup" / "run-2.json")
    for conversation in conversations:
        roles = [message["role"] for message in conversation["messages"]]
        assert roles == ["user", "assistant"] * (len(roles) // 2)
        answers = [m["content"] for m in conversation["messages"] if m["role"] == "assistant"]
        actor = "user" if conversation["role"] == "user" else "assistant"
        steps = [
            s for s in trajectory.steps if s.actor == actor and (s.mode or "user") == conversation["role"]
        ]
        assert answers == [s.action.raw for s in steps][: len(answers)]
    user = next(c for c in conversations if c["role"] == "user")
    assert "Observation: " in user["messages"][2]["content"]  # the previous step's result comes back
    only_user = tmp_path / "user.jsonl"
    assert main(["export", str(run), "-f", "sft", "--role", "user", "-o", str(only_user)]) == 0
    assert [c["role"] for c in _conversations(only_user)] == ["user"]


def test_bad_export_requests_are_refused_by_name(runs: Runs, tmp_path: Path, capsys) -> None:
    out = str(tmp_path / "out")
    assert main(["export", str(runs.oracle), "--format", "csv", "-o", out]) == 2
    assert "'csv'" in capsys.readouterr().err
    assert main(["export", str(runs.oracle), "--relationship", "friend", "-o", out]) == 2
    assert "'friend'" in capsys.readouterr().err
    assert main(["export", str(tmp_path / "nowhere"), "-o", out]) == 2
    assert "nowhere" in capsys.readouterr().err
    assert main(["export", str(runs.oracle), "-f", "sft", "--role", "judge", "-o", out]) == 2
    assert "'judge'" in capsys.readouterr().err


def test_inspect_s_own_reader_opens_the_log(runs: Runs, tmp_path: Path) -> None:
    inspect_log = pytest.importorskip(
        "inspect_ai.log", reason="the inspect extra is not installed (pip install -e '.[inspect]')"
    )
    assert main(["export", str(runs.models), "--format", "inspect", "-o", str(tmp_path)]) == 0
    (log_file,) = list(tmp_path.glob("*.json"))
    log = inspect_log.read_eval_log(str(log_file))
    loaded = load_run(runs.models)
    assert log.status == "success"
    assert log.eval.task == "pare-bench"
    assert log.eval.model == "test-assistant"
    roles = {role: config.model for role, config in (log.eval.model_roles or {}).items()}
    assert roles["user"] == "test-user" and roles["observe"] == "test-assistant"
    assert log.samples is not None
    assert sorted((str(s.id), s.epoch) for s in log.samples) == sorted(
        (r.scenario_id, r.run) for r in loaded.records
    )
    assert {s.scores["pare_checks"].value for s in log.samples if s.scores} == {"I"}
    assert log.results is not None
    (score,) = log.results.scores
    assert score.metrics["accuracy"].value == 0.0
