"""A damaged model-call cache is named with its problem, never a traceback, and never a reason for every
episode to fail silently: garbage, a cut-short file and a table of another shape stop with a clear error;
one damaged stored answer is asked again (or, when replaying, is that episode's cache miss naming its key).
A cache closed after a clean exit holds every answer in its one file (nothing left in the write-ahead log).
"""

from __future__ import annotations

import json
import shutil
import sqlite3
from pathlib import Path

import pytest

from pare.agents.models.cache import ModelCallCache
from pare.agents.models.types import Completion
from pare.cli import main
from pare.errors import CacheMiss, UserInputError
from pare.testing import ChatServer, proactive_play
from pare.testing.generation import ScriptedGeneration
from tests.generate.conftest import BENCH, example_answers
from tests.hardening.conftest import KEY_VARIABLE

REQUEST = {"backend": "openai", "model": "m"}


def answer(text: str = "hello") -> Completion:
    return Completion(text=text, model="m", cost_usd=None, latency_s=0.1)


def recorded(path: Path, count: int = 50) -> Path:
    cache = ModelCallCache(path)
    for number in range(count):
        cache.put(f"key-{number}", answer(f"answer {number} " + "x" * 2000), request=REQUEST, role="user")
    cache.close()
    return path


def test_a_file_that_is_not_a_cache_is_named(tmp_path: Path) -> None:
    garbage = tmp_path / "model_calls.sqlite"
    garbage.write_bytes(b"this is not a database at all\n" * 200)
    with pytest.raises(UserInputError, match=r"model-call cache .*model_calls\.sqlite.* not a PARE cache"):
        ModelCallCache(garbage)


def test_a_cut_short_cache_is_named_when_opened_or_read(tmp_path: Path) -> None:
    path = recorded(tmp_path / "model_calls.sqlite")
    data = path.read_bytes()
    path.write_bytes(data[: len(data) // 3])
    with pytest.raises(UserInputError, match=r"model-call cache .*model_calls\.sqlite"):
        cache = ModelCallCache(path)
        for number in range(50):
            cache.get(f"key-{number}")


def test_a_table_of_another_shape_is_not_a_cache(tmp_path: Path) -> None:
    path = tmp_path / "model_calls.sqlite"
    with sqlite3.connect(path) as connection:
        connection.execute("CREATE TABLE completions (key TEXT PRIMARY KEY, answer TEXT)")
    with pytest.raises(UserInputError, match="not a PARE cache: its table 'completions' lacks"):
        ModelCallCache(path)


def poison(path: Path, key: str, text: str = '{"content": 12') -> None:
    with sqlite3.connect(path) as connection:
        connection.execute("UPDATE completions SET completion = ? WHERE key = ?", (text, key))
    connection.close()


def test_a_poisoned_answer_is_asked_again_and_replaced(tmp_path: Path) -> None:
    path = recorded(tmp_path / "model_calls.sqlite", count=2)
    poison(path, "key-1")
    cache = ModelCallCache(path)
    assert cache.get("key-0") is not None
    assert cache.get("key-1") is None  # a miss: the model is asked again ...
    assert cache.put("key-1", answer("fresh"), request=REQUEST, role="user")  # ... and its answer kept
    stored = cache.get("key-1")
    assert stored is not None and stored.text == "fresh"


def test_a_poisoned_answer_in_replay_is_a_miss_naming_its_key(tmp_path: Path) -> None:
    path = recorded(tmp_path / "model_calls.sqlite", count=2)
    poison(path, "key-1", "[]")
    cache = ModelCallCache(path, mode="replay")
    with pytest.raises(CacheMiss, match="key-1 is damaged"):
        cache.get("key-1")


def test_closing_folds_the_log_into_the_file(tmp_path: Path) -> None:
    path = recorded(tmp_path / "model_calls.sqlite")
    wal = path.with_name(path.name + "-wal")
    assert not wal.exists() or wal.stat().st_size == 0
    alone = tmp_path / "copy" / "model_calls.sqlite"
    alone.parent.mkdir()
    shutil.copyfile(path, alone)  # the file alone, as a user copies it
    assert len(ModelCallCache(alone, mode="replay")) == 50


def run_argv(output: Path, scenario: Path, server: ChatServer, *extra: str) -> list[str]:
    argv = ["run", "--output", str(output), "--no-progress", "--runs", "1", "--scenario-path", str(scenario)]
    argv += ["--assistant-model", "a", "--assistant-endpoint", server.base_url]
    argv += ["--user-model", "u", "--user-endpoint", server.base_url]
    for role in ("user", "assistant"):
        argv += [
            "--set",
            f"models.{role}.api_key_env={KEY_VARIABLE}",
            "--set",
            f"models.{role}.max_retries=0",
        ]
    return [*argv, "--set", "episode_retries=0", *extra]


def test_a_run_on_a_garbage_cache_stops_naming_it(
    tmp_path: Path, example_scenario: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    garbage = tmp_path / "calls.sqlite"
    garbage.write_bytes(b"\x00garbage" * 1000)
    with ChatServer(proactive_play()) as server:
        code = main(run_argv(tmp_path / "run", example_scenario, server, "--set", f"cache_path={garbage}"))
    err = " ".join(capsys.readouterr().err.split())
    assert code == 2 and str(garbage) in err and "not a PARE cache" in err and "Traceback" not in err


def test_replaying_a_poisoned_cache_names_the_cache_and_key_not_internal_error(
    tmp_path: Path, example_scenario: Path
) -> None:
    with ChatServer(proactive_play()) as server:
        assert main(run_argv(tmp_path / "first", example_scenario, server)) == 0
    cache = tmp_path / "first" / "model_calls.sqlite"
    with sqlite3.connect(cache) as connection:
        connection.execute("UPDATE completions SET completion = 'not json'")
    connection.close()
    with ChatServer(proactive_play()) as server:
        argv = run_argv(tmp_path / "again", example_scenario, server, "--cache", "replay")
        main([*argv, "--set", f"cache_path={cache}"])
    record = json.loads((tmp_path / "again" / "episodes.jsonl").read_text(encoding="utf-8").splitlines()[0])
    assert record["failure"]["kind"] == "cache_miss"
    assert str(cache) in record["failure"]["message"] and "is damaged" in record["failure"]["message"]


def test_generate_leaves_its_whole_cache_in_the_one_file(tmp_path: Path) -> None:
    library = tmp_path / "library"
    library.mkdir()
    name = "book_club_pick_paperback.yaml"
    (library / name).write_text((BENCH / name).read_text(encoding="utf-8"), encoding="utf-8")
    answers = {stage: [text] for stage, text in example_answers().items()}
    with ChatServer(ScriptedGeneration({1: answers})) as server:
        argv = ["generate", "--apps", "email,calendar", "-n", "1", "-o", str(tmp_path / "out")]
        argv += ["--endpoint", server.base_url, "--library", str(library), "--no-progress"]
        assert main([*argv, "--model", "pare-generator"]) == 0
    cache = next((tmp_path / "out").rglob("*.sqlite"))
    wal = cache.with_name(cache.name + "-wal")
    assert not wal.exists() or wal.stat().st_size == 0
    alone = tmp_path / "alone.sqlite"
    shutil.copyfile(cache, alone)
    assert len(ModelCallCache(alone, mode="replay")) >= 4
