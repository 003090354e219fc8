"""A run as an Inspect evaluation log (an ``EvalLog`` in Inspect's JSON log format, version 2), written
without depending on Inspect: one log per run folder, one sample per complete episode (its id the
scenario, its epoch the run), scored by PARE's verdict.

The sample's conversation puts the assistant under evaluation in the model's seat: its steps are
assistant messages with their tool calls (what the model wrote, verbatim, as the content), each followed
by the tool's answer; the simulated user's steps are user messages (what it wrote, or its action for a
scripted user), with the action and its result in the message's metadata. Token usage is given per model
and per role (``role_usage``: user, observe, execute, judge), as Inspect keeps it. docs/exporting.md has
the whole mapping and what is left empty (events, the store: PARE does not record Inspect's events).
"""

from __future__ import annotations

import hashlib
import json
import re
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from pare.agents.models.ledger import RoleUsage
from pare.errors import UserInputError
from pare.results.exports.episodes import (
    Episode,
    complete_episodes,
    first_start,
    manifest_text,
    role_players,
)
from pare.results.metrics import ConfigurationMetrics, compute_metrics
from pare.results.run_folder import LoadedRun
from pare.results.trajectory import StepRecord

LOG_VERSION = 2
"""The Inspect log format version written."""
TASK = "pare-bench"
SCORER = "pare_checks"
CORRECT, INCORRECT = "C", "I"
"""Inspect's values for a right and a wrong answer (what its accuracy metric reads)."""


@dataclass(frozen=True)
class InspectLog:
    """What an export wrote."""

    file: Path
    samples: int


def export_inspect(run: LoadedRun, out: Path) -> InspectLog:
    """Write ``run`` as one Inspect JSON log into the folder ``out`` and return it.

    Raises:
        UserInputError: A trajectory that cannot be read, or a write refused.
    """
    metrics = compute_metrics(
        run.records, label=run.label, runs=run.runs, planned=run.planned, params=run.sweep_point
    )
    manifest = run.manifest
    players = role_players(manifest)
    models = _role_models(manifest, players)
    seed = f"{manifest_text(manifest, 'identity_hash')}|{run.path.name}"
    eval_id = hashlib.sha256(seed.encode("utf-8")).hexdigest()[:22]
    created = first_start(manifest) or "1970-01-01T00:00:00+00:00"
    episodes = list(complete_episodes(run))
    samples = [_sample(episode, players["assistant"], models) for episode in episodes]
    log = {
        "version": LOG_VERSION,
        "status": "success" if metrics.episodes_complete == metrics.episodes_planned else "error",
        "eval": _spec(run, eval_id, created, players, models, [s["id"] for s in samples]),
        "plan": {
            "name": "pare",
            "steps": [{"solver": "pare_turn_loop", "params": {}, "params_passed": {}}],
            "config": {},
        },
        "results": _results(metrics),
        "stats": {
            "started_at": created,
            "completed_at": "",
            "model_usage": _by_model((e.record.usage for e in episodes), models),
            "role_usage": _by_role(e.record.usage for e in episodes),
            "connection_limit_history": [],
        },
        "invalidated": False,
        "tags": [],
        "metadata": {"configuration": run.label, "run_folder": run.path.name},
        "samples": samples,
    }
    if log["status"] == "error":
        missing = metrics.episodes_planned - metrics.episodes_complete
        log["error"] = {
            "message": f"{missing} of {metrics.episodes_planned} planned episodes are not complete",
            "traceback": "",
            "traceback_ansi": "",
        }
    name = f"{re.sub(r'[^0-9A-Za-z]+', '-', created).strip('-')}_{TASK}_{eval_id}.json"
    file = out / name
    try:
        out.mkdir(parents=True, exist_ok=True)
        file.write_text(json.dumps(log, indent=2, ensure_ascii=False) + "\n", encoding="utf-8")
    except OSError as error:
        raise UserInputError(f"{out}: cannot write the Inspect log: {error.strerror or error}") from None
    return InspectLog(file=file, samples=len(samples))


def _spec(
    run: LoadedRun,
    eval_id: str,
    created: str,
    players: Mapping[str, str],
    models: Mapping[str, str],
    sample_ids: list[str],
) -> dict[str, Any]:
    return {
        "eval_id": eval_id,
        "run_id": eval_id,
        "created": created,
        "task": TASK,
        "task_id": manifest_text(run.manifest, "scenario_set_hash") or "unknown",
        "task_version": 0,
        "task_attribs": {},
        "task_args": {},
        "task_args_passed": {},
        "dataset": {"name": TASK, "samples": len(run.planned), "sample_ids": sorted(set(sample_ids))},
        "model": players["assistant"],
        "model_generate_config": {},
        "model_args": {},
        "model_roles": {role: {"model": model, "config": {}, "args": {}} for role, model in models.items()},
        "config": {"epochs": run.runs},
        "packages": {"pare-bench": manifest_text(run.manifest, "provenance", "pare") or "unknown"},
        "metadata": {
            "configuration": run.label,
            "user": players["user"],
            "judge": players["judge"],
            "protocol": manifest_text(run.manifest, "protocol", "preset") or "pare",
        },
    }


def _results(metrics: ConfigurationMetrics) -> dict[str, Any]:
    """The verdict's metrics as one Inspect score: accuracy (the success rate) with its standard error,
    and PARE's other headline numbers beside it where they were measured.
    """
    values: dict[str, float | None] = {
        "accuracy": metrics.success_rate.mean,
        "stderr": metrics.success_rate.se,
        "goal_rate": metrics.goal_rate.mean,
        "acceptance_rate": metrics.acceptance_rate.mean,
        "side_effect_rate": metrics.side_effect_rate.mean,
        **{f"pass_hat_{k}": value for k, value in sorted(metrics.pass_hat.items())},
    }
    if metrics.success_rate_ci is not None:
        values["ci_lower"], values["ci_upper"] = metrics.success_rate_ci
    return {
        "total_samples": metrics.episodes_planned,
        "completed_samples": metrics.episodes_complete,
        "scores": [
            {
                "name": SCORER,
                "scorer": SCORER,
                "params": {},
                "scored_samples": metrics.episodes_complete,
                "unscored_samples": metrics.episodes_planned - metrics.episodes_complete,
                "metrics": {
                    name: {"name": name, "value": value, "params": {}}
                    for name, value in values.items()
                    if value is not None
                },
            }
        ],
    }


def _sample(episode: Episode, assistant: str, models: Mapping[str, str]) -> dict[str, Any]:
    record, trajectory = episode.record, episode.trajectory
    messages = _messages(trajectory.steps, assistant)
    last_answer = next(
        (m["content"] for m in reversed(messages) if m["role"] == "assistant" and m["content"]), ""
    )
    goals = trajectory.outcome.goals
    return {
        "id": record.scenario_id,
        "epoch": record.run,
        "input": f"PARE scenario {record.scenario_id}",
        "target": [goal.description or goal.id for goal in goals],
        "messages": messages,
        "output": {"model": assistant, "choices": [], "completion": last_answer},
        "scores": {
            SCORER: {
                "value": CORRECT if record.success else INCORRECT,
                "answer": record.ended,
                "explanation": "; ".join(f"{g.id}: {'met' if g.passed else 'not met'}" for g in goals)
                + f"; side effects: {record.side_effects}",
                "history": [],
                "metadata": {"goals": dict(record.goals), "goal_rate": record.goal_rate},
            }
        },
        "metadata": {
            "seed": record.seed,
            "scenario_hash": record.scenario_hash,
            "difficulty": record.difficulty,
            "kind": record.kind,
            "apps": list(record.apps),
            "tags": list(record.tags),
            "turns": record.turns,
        },
        "store": {},
        "events": [],
        "model_usage": _by_model([record.usage], models),
        "role_usage": _by_role([record.usage]),
        "total_time": record.wall_s,
        "attachments": {},
    }


def _messages(steps: Iterable[StepRecord], assistant: str) -> list[dict[str, Any]]:
    messages: list[dict[str, Any]] = []
    for number, step in enumerate(steps):
        action = step.action
        if step.actor == "user":
            written = action.raw or f"{action.tool}({json.dumps(action.args, ensure_ascii=False)})"
            messages.append(
                {
                    "role": "user",
                    "content": written,
                    "metadata": {
                        "turn": step.turn,
                        "tool": action.tool,
                        "args": action.args,
                        "ok": step.ok,
                        "observation": step.observation,
                    },
                }
            )
            continue
        call_id = f"step-{number}"
        messages.append(
            {
                "role": "assistant",
                "content": action.raw or "",
                "model": assistant,
                "tool_calls": [
                    {"id": call_id, "function": action.tool, "arguments": action.args, "type": "function"}
                ],
                "metadata": {"turn": step.turn, "mode": step.mode},
            }
        )
        tool: dict[str, Any] = {
            "role": "tool",
            "content": step.observation,
            "tool_call_id": call_id,
            "function": action.tool,
        }
        if not step.ok:
            tool["error"] = {"type": "unknown", "message": action.error or step.observation}
        messages.append(tool)
    return messages


def _usage(usage: RoleUsage) -> dict[str, Any]:
    return {
        "input_tokens": usage.prompt_tokens,
        "output_tokens": usage.completion_tokens,
        "total_tokens": usage.total_tokens,
        "input_tokens_cache_read": usage.cached_tokens,
        "total_cost": usage.cost_usd,
    }


def _by_role(usages: Iterable[Mapping[str, RoleUsage]]) -> dict[str, Any]:
    totals: dict[str, RoleUsage] = {}
    for usage in usages:
        for role, role_usage in usage.items():
            totals[role] = totals.get(role, RoleUsage()) + role_usage
    return {role: _usage(total) for role, total in sorted(totals.items())}


def _by_model(usages: Iterable[Mapping[str, RoleUsage]], models: Mapping[str, str]) -> dict[str, Any]:
    totals: dict[str, RoleUsage] = {}
    for usage in usages:
        for role, role_usage in usage.items():
            model = models.get(role, role)
            totals[model] = totals.get(model, RoleUsage()) + role_usage
    return {model: _usage(total) for model, total in sorted(totals.items())}


def _role_models(manifest: Mapping[str, Any], players: Mapping[str, str]) -> dict[str, str]:
    """Each model role's model name (the roles of a run's usage), as the manifest records it."""
    found = {
        role: manifest_text(manifest, "identity", "models", role, "model")
        for role in ("user", "observe", "execute", "judge")
    }
    if found["judge"] is None:
        found["judge"] = manifest_text(manifest, "judge", "model")
    return {role: model for role, model in found.items() if model}
