"""Personas of trust: a protocol setting that words how the user decides proposals, told to the user model,
recorded in the manifest and the reports' heading, and part of a run's identity only when not the default.
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from pare.agents.prompts import user_system_prompt
from pare.bench.runconfig import RunConfig, build_config
from pare.env import Environment
from pare.errors import UserInputError
from pare.protocols import ProtocolSettings, manifest_protocol
from pare.results.run_folder import SWEEP_FILE, load_run
from pare.sim.budget import USER_TRUST, TurnBudget


def _assistant_section(trust: str) -> str:
    prompt = user_system_prompt(Environment(["email"]), budget=TurnBudget(user_trust=trust))  # type: ignore[arg-type]
    section = prompt.split("## Your assistant", 1)[1].split("\n## ", 1)[0]
    return " ".join(section.split())


def test_each_persona_words_the_users_decision_its_own_way() -> None:
    sections = {trust: _assistant_section(trust) for trust in USER_TRUST}
    assert len(set(sections.values())) == len(USER_TRUST)
    assert "Be a demanding user" in sections["demanding"]
    assert "check the one thing you need first" in sections["demanding"]
    assert "you do not check it in your apps first" in sections["trusting"]
    assert "rarely take the time to check" in sections["busy"]
    assert "Before you answer any proposal, check in your apps" in sections["sceptical"]
    for trust in USER_TRUST:  # what every persona is told of the protocol stays
        assert "A proposal waits 4 turns for your answer" in sections[trust]
        assert "Once you accept, the assistant carries the task out" in sections[trust]


def test_the_default_persona_is_the_demanding_user_of_every_earlier_run() -> None:
    env = Environment(["email"])
    assert user_system_prompt(env) == user_system_prompt(env, budget=TurnBudget(user_trust="demanding"))
    assert TurnBudget().user_trust == "demanding"


def test_a_persona_with_the_papers_wording_is_refused_with_the_reason() -> None:
    with pytest.raises(UserInputError, match=r"user_trust 'trusting'.*user_prompt is 'paper'"):
        build_config({"protocol": {"preset": "paper", "user_trust": "trusting"}})
    with pytest.raises(UserInputError, match="user_trust"):
        build_config({"protocol": {"user_trust": "gullible"}})


def test_a_persona_enters_the_identity_manifest_and_heading_only_when_not_the_default() -> None:
    default = RunConfig()
    trusting = build_config({"protocol": {"user_trust": "trusting"}})
    assert "user_trust" not in default.identity()["protocol"]  # earlier run folders keep resuming
    assert trusting.identity()["protocol"]["user_trust"] == "trusting"
    assert trusting.identity_hash() != default.identity_hash()
    record = trusting.protocol.record()
    assert record["settings"]["user_trust"] == "trusting"
    assert manifest_protocol({"protocol": record}) == ("pare", {"user_trust": "trusting"})
    assert ProtocolSettings().overrides() == {}


def test_the_run_flag_sets_the_persona() -> None:
    from pare.cli.run_cmd import collect_overrides, load_config

    overrides = collect_overrides(sets=None, flags={"protocol.user_trust": "sceptical"}, models={})
    assert load_config(None, overrides).protocol.budget().user_trust == "sceptical"


def test_a_sweep_takes_the_persona_as_an_axis(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    from pare.cli import main

    grid = "protocol.user_trust=[demanding, sceptical]"
    argv = ["sweep", "-g", grid, "--set", "scenarios.split=smoke", "--set", "runs=1"]
    assert main([*argv, "-o", str(tmp_path / "trust"), "--no-progress"]) == 0
    described = json.loads((tmp_path / "trust" / SWEEP_FILE).read_text(encoding="utf-8"))
    points = {p["params"]["protocol.user_trust"]: p["folder"] for p in described["points"]}
    assert set(points) == {"demanding", "sceptical"}
    sceptical = load_run(tmp_path / "trust" / points["sceptical"])
    assert manifest_protocol(sceptical.manifest) == ("pare", {"user_trust": "sceptical"})
    assert (
        "user_trust"
        not in load_run(tmp_path / "trust" / points["demanding"]).manifest["identity"]["protocol"]
    )
    capsys.readouterr()
    assert main(["report", str(tmp_path / "trust" / points["sceptical"]), "--format", "markdown"]) == 0
    assert "user_trust=sceptical" in capsys.readouterr().out.splitlines()[0]
