"""A judge model's reason, from a run against a local chat server to the episode page."""

from __future__ import annotations

import html
from pathlib import Path
from typing import Any

from pare.bench import build_config, run_benchmark
from pare.testing import ChatServer, Reply, completion
from pare.viewer import Catalog, Site
from tests.scenarios.helpers import base, to_yaml

REASON = "The reply accepts Thursday but puts the dinner at Marco's, which the facts do not name."


def test_the_judges_reason_reaches_the_trajectory_and_the_page(tmp_path: Path) -> None:
    data = base()
    judged = {
        "criterion": "says yes to Thursday",
        "action": {"tool": "email__reply_to_email"},
        "fallback": {"contains": "thursday"},
        "facts": ["The dinner is at Luigi's."],
    }
    data["goals"] = [{"id": "g", "description": "replied yes", "checks": [{"judge": judged}]}]
    folder = tmp_path / "scenarios"
    folder.mkdir()
    (folder / "tiny_reply.yaml").write_text(to_yaml(data))
    asked: list[dict[str, Any]] = []

    def judge(body: dict[str, Any]) -> Reply:
        asked.append(body)
        return completion(f"NO\n{REASON}", prompt_tokens=60, completion_tokens=20)

    with ChatServer(judge) as server:
        judge_model = {"model": "judge-model", "api_base": server.base_url, "api_key_env": None}
        config = build_config(
            {
                "scenarios": {"paths": [str(folder)]},
                "runs": 1,
                "output": str(tmp_path / "run"),
                "models": {"judge": judge_model},
            }
        )
        run_benchmark(config)
    (request,) = asked
    assert "Facts:\n- The dinner is at Luigi's.\n" in request["messages"][-1]["content"]
    configuration = Catalog.open([tmp_path / "run"]).configurations[0]
    record = configuration.records[("tiny_reply", 1)]
    trajectory = configuration.trajectory(record)
    assert trajectory is not None
    (check,) = trajectory.outcome.goals[0].checks
    assert not check.passed and check.detail.endswith(f" | the judge: {REASON}")
    page = Site(Catalog.open([tmp_path / "run"])).page("c/run/e/tiny_reply/run-1.html")
    assert page is not None
    text = html.unescape(page.body.decode())
    shown = text.split('<span class="form">judge</span>', 1)[1].split("</li>", 1)[0]
    assert f'<div class="judge-said">the judge: {REASON}</div>' in shown
    assert "| the judge:" not in shown  # the reason is shown apart, not twice
