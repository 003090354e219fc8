"""Run configurations: files, flags and --set overrides, identity, labels and the default folder."""

from __future__ import annotations

from datetime import timedelta
from pathlib import Path

import pytest

from pare.bench.runconfig import RunConfig, build_config, parse_assignment, read_config_file
from pare.errors import UserInputError


def test_defaults_are_the_papers_protocol() -> None:
    config = RunConfig()
    assert config.runs == 4
    assert config.oracle_only
    protocol = config.protocol
    assert (protocol.max_turns, protocol.user_steps, protocol.observe_steps, protocol.execute_steps) == (
        10,
        1,
        5,
        10,
    )
    assert config.label() == "oracle"
    assert config.output_dir().parent == Path("runs")
    assert config.output_dir().name.startswith("oracle-")


def test_file_then_overrides(tmp_path: Path) -> None:
    file = tmp_path / "run.yaml"
    file.write_text(
        "runs: 2\n"
        "models:\n  assistant: {model: gpt-4o, api_base: 'http://localhost:8000/v1'}\n"
        "  user: {model: gpt-5-mini}\n"
        "protocol: {max_turns: 12, turn_duration: 90s}\n"
    )
    config = build_config(
        read_config_file(file),
        overrides=[
            ("runs", 3),
            parse_assignment("world.noise_rate_per_minute=2"),
            ("models.user.temperature", 0.5),
        ],
    )
    assert config.runs == 3
    assert config.world.noise_rate_per_minute == 2.0
    assert config.protocol.turn_duration == timedelta(seconds=90)
    assert config.models.observe is not None and config.models.observe.model == "gpt-4o"
    assert config.models.execute == config.models.observe  # the symmetric setup
    assert config.models.user is not None and config.models.user.temperature == 0.5
    assert config.label() == "gpt-4o (user gpt-5-mini)"
    settings = config.episode_settings(seed=5)
    assert settings.max_turns == 12 and settings.env.seed == 5 and settings.env.noise_rate_per_minute == 2.0


def test_every_problem_is_listed_with_its_path() -> None:
    with pytest.raises(UserInputError) as caught:
        build_config({"runs": 0, "protocol": {"max_turn": 3}, "models": {"user": {"temperature": 1}}})
    message = str(caught.value)
    assert "runs:" in message
    assert "protocol.max_turn:" in message
    assert "models.user.model:" in message


def test_keys_are_never_configuration() -> None:
    with pytest.raises(UserInputError, match="NAME of an environment variable"):
        build_config({"models": {"user": {"model": "m", "api_key_env": "sk-abcdef"}}})
    with pytest.raises(UserInputError, match="api_key"):
        build_config({"models": {"user": {"model": "m", "api_key": "sk-abcdef"}}})


def test_set_reads_yaml_values_and_rejects_bad_ones() -> None:
    assert parse_assignment("scenarios.ids=[a, b]") == ("scenarios.ids", ["a", "b"])
    assert parse_assignment("models.judge=null") == ("models.judge", None)
    with pytest.raises(UserInputError, match="path=value"):
        parse_assignment("max_turns")
    with pytest.raises(UserInputError, match="is a value"):
        build_config({"runs": 2}, overrides=[("runs.deep", 1)])


def test_identity_covers_what_shapes_episodes_only() -> None:
    base = build_config({"models": {"assistant": {"model": "a"}}})
    same = build_config(
        {
            "models": {"assistant": {"model": "a", "timeout_s": 5, "max_concurrency": 2}},
            "runs": 9,
            "concurrency": 1,
        }
    )
    assert base.identity_hash() == same.identity_hash()
    for change in (
        {"seed": 1},
        {"models": {"assistant": {"model": "a", "temperature": 0.7}}},
        {"models": {"assistant": {"model": "a"}}, "world": {"tool_failure_probability": 0.1}},
        {"models": {"assistant": {"model": "a"}}, "protocol": {"max_turns": 20}},
    ):
        assert (
            build_config({"models": {"assistant": {"model": "a"}}, **change}).identity_hash()
            != base.identity_hash()
        )


def test_episode_seeds_differ_per_scenario_and_run_and_are_stable() -> None:
    config = RunConfig()
    seeds = {config.episode_seed(s, r) for s in ("a", "b") for r in (1, 2)}
    assert len(seeds) == 4
    assert config.episode_seed("a", 1) == RunConfig().episode_seed("a", 1)
    assert RunConfig(seed=1).episode_seed("a", 1) != config.episode_seed("a", 1)


def test_unreadable_files_are_named(tmp_path: Path) -> None:
    with pytest.raises(UserInputError, match="cannot read"):
        read_config_file(tmp_path / "missing.yaml")
    bad = tmp_path / "bad.yaml"
    bad.write_text("runs: [1\n")
    with pytest.raises(UserInputError, match="not valid YAML"):
        read_config_file(bad)
    listed = tmp_path / "list.yaml"
    listed.write_text("- 1\n")
    with pytest.raises(UserInputError, match="mapping"):
        read_config_file(listed)


def test_modes_fill_in_from_each_other() -> None:
    observe_only = build_config({"models": {"observe": {"model": "small"}}})
    assert observe_only.models.execute is not None and observe_only.models.execute.model == "small"
    split = build_config({"models": {"assistant": {"model": "a"}, "execute": {"model": "big"}}})
    assert split.models.observe is not None and split.models.observe.model == "a"
    assert split.models.execute is not None and split.models.execute.model == "big"
    assert split.label() == "a+big"
    with pytest.raises(UserInputError, match="needs an observe model"):
        build_config({"models": {"execute": {"model": "big"}}})
