"""A run in the Every Eval Ever schema (EvalEval, schema version 0.3.0): one aggregate file with the
configuration's metrics and their uncertainty, and a JSON-lines file of instance records, one per complete
episode, with its messages and token usage.

The files are laid out as that project's data store lays them out, under the folder given::

    data/pare-bench/<developer>/<model>/<uuid>.json            the aggregate (eval.schema.json)
    data/pare-bench/<developer>/<model>/<uuid>_samples.jsonl   the instances (instance_level_eval.schema.json)

so the aggregate's ``detailed_evaluation_results.file_path`` names the instances file as the schema asks
(repository-relative, rooted at ``data/``). The uuid is derived from the run's identity, so exporting the
same run again writes the same files. docs/exporting.md gives the whole mapping.
"""

from __future__ import annotations

import hashlib
import json
import re
import uuid
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from datetime import UTC, datetime
from pathlib import Path
from typing import Any
from urllib.parse import urlparse

from pare.agents.models.ledger import RoleUsage
from pare.errors import UserInputError
from pare.results.exports.episodes import (
    Episode,
    complete_episodes,
    first_start,
    manifest_text,
    role_players,
)
from pare.results.metrics import ConfigurationMetrics, Estimate, compute_metrics
from pare.results.run_folder import LoadedRun
from pare.results.trajectory import StepRecord

SCHEMA_VERSION = "0.3.0"
"""The Every Eval Ever schema version written."""
COLLECTION = "pare-bench"
"""The data store's folder for this benchmark (its results' ``source_data.dataset_name``)."""
PRIMARY = "pare.success_rate"
"""The aggregate result the instance records belong to: each episode's score is its success."""
RELATIONSHIPS = ("first_party", "third_party", "collaborative", "other")
_LOOPBACK = {"127.0.0.1", "localhost", "::1"}


@dataclass(frozen=True)
class EeeFiles:
    """What an export wrote."""

    aggregate: Path
    samples: Path
    instances: int


@dataclass(frozen=True)
class _Model:
    """The evaluated assistant, named as the schema wants it."""

    id: str
    developer: str
    name: str
    platform: str | None
    deployment: str


def export_eee(
    run: LoadedRun,
    out: Path,
    *,
    organization: str = "unknown",
    relationship: str = "third_party",
    retrieved: datetime | None = None,
) -> EeeFiles:
    """Write ``run`` under ``out`` in the Every Eval Ever layout and return the files written.

    Args:
        run: The run folder, as :func:`pare.results.run_folder.load_run` reads it.
        out: The folder the ``data/`` tree is written into.
        organization: Who ran the evaluation (``source_metadata.source_organization_name``).
        relationship: The evaluator's relation to the model: one of :data:`RELATIONSHIPS`.
        retrieved: When the record is made (now by default).

    Raises:
        UserInputError: An unknown relationship, a trajectory that cannot be read, or a write refused.
    """
    if relationship not in RELATIONSHIPS:
        raise UserInputError(f"--relationship {relationship!r}: choose one of {', '.join(RELATIONSHIPS)}")
    metrics = compute_metrics(
        run.records, label=run.label, runs=run.runs, planned=run.planned, params=run.sweep_point
    )
    model = _assistant_model(run.manifest)
    moment = retrieved or datetime.now(UTC)
    evaluation_id = f"{COLLECTION}/{model.id}/{int(moment.timestamp())}"
    file_id = _file_uuid(run)
    folder = Path("data") / COLLECTION / _path_part(model.developer) / _path_part(model.name)
    samples_name = f"{file_id}_samples.jsonl"
    lines = [
        json.dumps(_instance(episode, evaluation_id, model.id), ensure_ascii=False, sort_keys=True)
        for episode in complete_episodes(run)
    ]
    samples_text = "".join(line + "\n" for line in lines)
    aggregate = _aggregate(run, metrics, model, evaluation_id, moment, organization, relationship)
    aggregate["detailed_evaluation_results"] = {
        "format": "jsonl",
        "file_path": (folder / samples_name).as_posix(),
        "hash_algorithm": "sha256",
        "checksum": hashlib.sha256(samples_text.encode("utf-8")).hexdigest(),
        "total_rows": len(lines),
    }
    target = out / folder
    samples = target / samples_name
    aggregate_file = target / f"{file_id}.json"
    try:
        target.mkdir(parents=True, exist_ok=True)
        samples.write_text(samples_text, encoding="utf-8")
        aggregate_file.write_text(
            json.dumps(aggregate, indent=2, ensure_ascii=False) + "\n", encoding="utf-8"
        )
    except OSError as error:
        raise UserInputError(f"{target}: cannot write the export: {error.strerror or error}") from None
    return EeeFiles(aggregate=aggregate_file, samples=samples, instances=len(lines))


# -- the aggregate ----------------------------------------------------------------------------------------
def _aggregate(
    run: LoadedRun,
    metrics: ConfigurationMetrics,
    model: _Model,
    evaluation_id: str,
    moment: datetime,
    organization: str,
    relationship: str,
) -> dict[str, Any]:
    manifest = run.manifest
    players = role_players(manifest)
    details = {
        "configuration": run.label,
        "user": players["user"],
        "judge": players["judge"],
        "protocol": metrics.protocol,
        "runs_per_scenario": str(run.runs),
    }
    if identity_hash := manifest_text(manifest, "identity_hash"):
        details["identity_hash"] = identity_hash
    document: dict[str, Any] = {
        "schema_version": SCHEMA_VERSION,
        "evaluation_id": evaluation_id,
        "retrieved_timestamp": str(int(moment.timestamp())),
        "source_metadata": {
            "source_name": "PARE (Proactive Agent Research Environment)",
            "source_type": "evaluation_run",
            "source_organization_name": organization,
            "evaluator_relationship": relationship,
            "additional_details": {"run_folder": run.path.name},
        },
        "eval_library": {
            "name": "pare-bench",
            "version": manifest_text(manifest, "provenance", "pare") or "unknown",
        },
        "model_info": _model_info(model, details),
        "evaluation_results": _results(run, metrics),
    }
    if started := first_start(manifest):
        document["evaluation_timestamp"] = started
    return document


def _model_info(model: _Model, details: Mapping[str, str]) -> dict[str, Any]:
    info: dict[str, Any] = {
        "name": model.name,
        "id": model.id,
        "developer": model.developer,
        "additional_details": {
            "deployment_type": model.deployment,
            "model_availability": "unknown",
            **details,
        },
    }
    if model.platform:
        info["inference_platform"] = model.platform
    return info


def _results(run: LoadedRun, metrics: ConfigurationMetrics) -> list[dict[str, Any]]:
    """The configuration's metrics as the schema's results: each with its uncertainty where PARE has one
    (the standard error across the k runs; the bootstrap interval of the success rate).
    """
    source = {
        "dataset_name": COLLECTION,
        "source_type": "other",
        "additional_details": {
            "scenarios": str(metrics.scenarios),
            "scenario_set_hash": manifest_text(run.manifest, "scenario_set_hash") or "unknown",
        },
    }
    k = run.runs
    rows: list[dict[str, Any]] = []

    def add(
        metric: str,
        name: str,
        description: str,
        score: float | None,
        *,
        lower_is_better: bool = False,
        estimate: Estimate | None = None,
        parameters: Mapping[str, int] | None = None,
        unit: str = "proportion",
        maximum: float | str = 1.0,
    ) -> dict[str, Any] | None:
        if score is None:  # not measured (no complete episode, no proposal, an unpriced call)
            return None
        config: dict[str, Any] = {
            "evaluation_description": description,
            "metric_id": metric,
            "metric_name": name,
            "metric_unit": unit,
            "lower_is_better": lower_is_better,
            "score_type": "continuous",
            "min_score": 0.0,
            "max_score": maximum,
        }
        if parameters:
            config["metric_parameters"] = dict(parameters)
        details: dict[str, Any] = {"score": score}
        if estimate is not None and estimate.se is not None:
            details["uncertainty"] = {
                "standard_error": {"value": estimate.se, "method": f"across the {estimate.n} runs"},
                "num_samples": metrics.episodes_complete,
            }
        row = {
            "evaluation_result_id": metric,
            "evaluation_name": f"{COLLECTION} {name}",
            "source_data": source,
            "metric_config": config,
            "score_details": details,
        }
        rows.append(row)
        return row

    success = add(
        PRIMARY,
        "success rate",
        "Share of complete episodes whose goals were all met without side effects.",
        metrics.success_rate.mean,
        estimate=metrics.success_rate,
    )
    if success is not None and metrics.success_rate_ci is not None:
        uncertainty = success["score_details"].setdefault("uncertainty", {})
        uncertainty["confidence_interval"] = {
            "lower": metrics.success_rate_ci[0],
            "upper": metrics.success_rate_ci[1],
            "confidence_level": metrics.confidence,
            "method": "bootstrap over scenarios",
        }
        uncertainty["num_bootstrap_samples"] = metrics.bootstrap_samples
        uncertainty["num_samples"] = metrics.episodes_complete
    add(
        "pare.goal_rate",
        "goal rate",
        "Share of goals met, averaged over complete episodes.",
        metrics.goal_rate.mean,
        estimate=metrics.goal_rate,
    )
    add(
        "pare.success_at_k",
        f"Success@{k}",
        f"Share of scenarios with at least one success among their {k} runs.",
        metrics.success_at_k,
        parameters={"k": k},
    )
    add(
        "pare.success_all_k",
        f"Success^{k}",
        f"Share of scenarios that succeeded in all {k} runs.",
        metrics.success_all_k,
        parameters={"k": k},
    )
    for n, value in sorted(metrics.pass_hat.items()):
        add(
            f"pare.pass_hat_{n}",
            f"pass^{n}",
            f"Chance that {n} runs of a scenario drawn without replacement all succeed (unbiased).",
            value,
            parameters={"k": n},
        )
    add(
        "pare.acceptance_rate",
        "acceptance rate",
        "Share of the assistant's proposals the user accepted.",
        metrics.acceptance_rate.mean,
        estimate=metrics.acceptance_rate,
    )
    add(
        "pare.proposal_rate",
        "proposal rate",
        "Proposals per turn.",
        metrics.proposal_rate.mean,
        estimate=metrics.proposal_rate,
        unit="proposals per turn",
        maximum="Infinity",
    )
    add(
        "pare.side_effect_rate",
        "side-effect rate",
        "Share of complete episodes failed because the assistant changed something no solution changes.",
        metrics.side_effect_rate.mean,
        estimate=metrics.side_effect_rate,
        lower_is_better=True,
    )
    total = metrics.usage.get("total")
    add(
        "pare.cost_per_success",
        "cost per success",
        "Cost of every model call of the complete episodes divided by the successes.",
        total.cost_per_success if total is not None else None,
        lower_is_better=True,
        unit="USD",
        maximum="Infinity",
    )
    return rows


# -- the instances ----------------------------------------------------------------------------------------
def _instance(episode: Episode, evaluation_id: str, model_id: str) -> dict[str, Any]:
    record, trajectory = episode.record, episode.trajectory
    messages = _messages(trajectory.steps)
    reference = [goal.description or goal.id for goal in trajectory.outcome.goals]
    raw = f"PARE scenario {record.scenario_id}"
    verdict = "success" if record.success else "failure"
    instance: dict[str, Any] = {
        "schema_version": SCHEMA_VERSION,
        "evaluation_id": evaluation_id,
        "model_id": model_id,
        "evaluation_name": f"{COLLECTION} success rate",
        "evaluation_result_id": PRIMARY,
        "sample_id": record.scenario_id,
        "sample_hash": _sample_hash(raw, reference),
        "interaction_type": "agentic",
        "input": {"raw": raw, "reference": reference},
        "output": None,
        "messages": messages,
        "answer_attribution": [
            {
                "turn_idx": max(len(messages) - 1, 0),
                "source": "the final state of the apps and the action log",
                "extracted_value": verdict,
                "extraction_method": "pare_checks",
                "is_terminal": True,
            }
        ],
        "evaluation": {
            "score": 1.0 if record.success else 0.0,
            "is_correct": record.success,
            "num_turns": record.turns if record.turns >= 1 else None,
            "tool_calls_count": len(trajectory.steps),
        },
        "metadata": _metadata(episode),
    }
    usage = _total_usage(record.usage.values())
    if usage.calls:
        instance["token_usage"] = {
            "input_tokens": usage.prompt_tokens,
            "output_tokens": usage.completion_tokens,
            "total_tokens": usage.total_tokens,
            "input_tokens_cache_read": usage.cached_tokens,
        }
    if record.wall_s > 0:
        instance["performance"] = {"latency_ms": record.wall_s * 1000}
    return instance


def _messages(steps: Iterable[StepRecord]) -> list[dict[str, Any]]:
    """Each step as the actor's message with its tool call, then the tool's answer: the simulated user's
    steps under ``user``, the assistant's (both modes) under ``assistant``.
    """
    messages: list[dict[str, Any]] = []
    for number, step in enumerate(steps):
        call_id = f"step-{number}"
        messages.append(
            {
                "turn_idx": len(messages),
                "role": step.actor,
                "content": step.action.raw,
                "reasoning_trace": step.action.reasoning,
                "tool_calls": [
                    {"id": call_id, "name": step.action.tool, "arguments": _strings(step.action.args)}
                ],
            }
        )
        messages.append(
            {
                "turn_idx": len(messages),
                "role": "tool",
                "content": step.observation,
                "tool_call_id": [call_id],
            }
        )
    return messages


def _metadata(episode: Episode) -> dict[str, str]:
    """The episode's facts as the schema's string-valued metadata, with tokens and cost per role."""
    record = episode.record
    data = {
        "run": str(record.run),
        "seed": str(record.seed),
        "scenario_hash": record.scenario_hash,
        "difficulty": record.difficulty,
        "kind": record.kind or "",
        "apps": ",".join(record.apps),
        "tags": ",".join(record.tags),
        "ended": record.ended,
        "goal_rate": str(record.goal_rate),
        "side_effects": str(record.side_effects),
        "proposals": str(len(record.proposals)),
        "accepted": str(record.accepted),
        "trajectory": record.trajectory or "",
    }
    for role, usage in sorted(record.usage.items()):
        data[f"tokens.{role}.input"] = str(usage.prompt_tokens)
        data[f"tokens.{role}.output"] = str(usage.completion_tokens)
        data[f"tokens.{role}.cached"] = str(usage.cached_tokens)
        cost = usage.cost_usd
        data[f"cost_usd.{role}"] = "unknown" if cost is None else f"{cost:.6f}"
    return data


def _total_usage(usages: Iterable[RoleUsage]) -> RoleUsage:
    total = RoleUsage()
    for usage in usages:
        total = total + usage
    return total


def _strings(args: Mapping[str, Any]) -> dict[str, str]:
    """Tool arguments with string values, as the schema wants them (others as JSON)."""
    return {
        key: value if isinstance(value, str) else json.dumps(value, ensure_ascii=False, sort_keys=True)
        for key, value in args.items()
    }


def _sample_hash(raw: str, reference: list[str]) -> str:
    """The schema's cross-model join key: SHA-256 of the input and its references, as its adapters hash."""
    text = json.dumps({"raw": raw, "reference": reference}, sort_keys=True, separators=(",", ":"))
    return hashlib.sha256(text.encode("utf-8")).hexdigest()


# -- naming -----------------------------------------------------------------------------------------------
def _assistant_model(manifest: Mapping[str, Any]) -> _Model:
    """The assistant under evaluation: its model (``developer/name`` when the name has a slash), or the
    policy that played it (``pare/oracle``).
    """
    name = manifest_text(manifest, "identity", "models", "observe", "model")
    if name is None:
        policy = role_players(manifest)["assistant"]
        return _Model(f"pare/{policy}", "pare", policy, None, "unknown")
    developer, _, short = name.rpartition("/")
    endpoint = manifest_text(manifest, "config", "models", "observe", "api_base")
    host = urlparse(endpoint).hostname if endpoint else None
    deployment = "self_deployed" if host in _LOOPBACK else ("externally_managed" if host else "unknown")
    backend = manifest_text(manifest, "identity", "models", "observe", "backend")
    return _Model(name, developer.split("/")[0] if developer else "unknown", short, backend, deployment)


def _path_part(text: str) -> str:
    """A name safe as one folder of the data store's layout."""
    return re.sub(r"[^A-Za-z0-9._-]+", "_", text).strip("._") or "unknown"


def _file_uuid(run: LoadedRun) -> str:
    """A version-4-shaped uuid derived from the run's identity (the schema's file names need one)."""
    seed = f"{manifest_text(run.manifest, 'identity_hash')}|{run.label}|{run.path.name}"
    return str(uuid.UUID(bytes=hashlib.sha256(seed.encode("utf-8")).digest()[:16], version=4))
