from __future__ import annotations

import asyncio
import multiprocessing
import sqlite3
from pathlib import Path
from typing import Any

import pytest

from pare.agents.models import (
    ChatMessage,
    Completion,
    ModelCallCache,
    ModelClient,
    ModelConfig,
    Prices,
    ToolCall,
    Usage,
    UsageLedger,
    cache_key,
    request_record,
)
from pare.errors import CacheMiss, UserInputError

from .conftest import BACKENDS, ConfigFactory
from .fake_server import FakeChatServer, answer, tool_call

HELLO = [ChatMessage.system("You are terse."), ChatMessage.user("Say hello.")]
TOOL = {"type": "function", "function": {"name": "f", "parameters": {"type": "object", "properties": {}}}}


def run(client: ModelClient, messages: list[ChatMessage] = HELLO) -> Completion:
    async def call() -> Completion:
        async with client:
            return await client.complete(messages, [TOOL])

    return asyncio.run(call())


@pytest.mark.parametrize("backend", BACKENDS)
def test_read_write_records_then_replays_byte_identically(
    backend: str, server: FakeChatServer, make_config: ConfigFactory, tmp_path: Path
) -> None:
    server.push(answer("Hi.", cached_tokens=300, tool_calls=[tool_call("c1", "f", {"x": 1})]))
    path = tmp_path / "calls.sqlite"
    config = make_config(
        backend, native_tools=True, prices=Prices(input=0.15, output=0.6, cached_input=0.075)
    )
    ledger = UsageLedger()
    client = ModelClient(config, role="user", cache=ModelCallCache(path, "read_write"), ledger=ledger)

    live = run(client)
    again = run(client)
    assert server.count == 1  # the second call was served from the cache
    assert not live.from_cache and again.from_cache
    assert again.model_copy(update={"from_cache": False}).model_dump_json() == live.model_dump_json()
    assert again.tool_calls == (ToolCall(id="c1", name="f", arguments='{"x": 1}'),)
    assert again.cost_usd == live.cost_usd is not None

    usage = ledger.role("user")
    assert (usage.calls, usage.cached_calls) == (2, 1)
    assert usage.cached_cost_usd == pytest.approx(live.cost_usd)

    # A later run in replay mode needs no server, no key and gives the same answer.
    replayer = ModelClient(config, role="user", cache=ModelCallCache(path, "replay"))
    replayed = run(replayer)
    assert replayed.model_dump_json() == again.model_dump_json()
    assert server.count == 1


def test_replay_miss_names_the_role_and_model(
    server: FakeChatServer, make_config: ConfigFactory, tmp_path: Path
) -> None:
    path = tmp_path / "calls.sqlite"
    ModelCallCache(path, "read_write")  # an empty, recorded cache
    client = ModelClient(make_config(), role="judge", cache=ModelCallCache(path, "replay"))
    with pytest.raises(CacheMiss) as raised:
        run(client)
    message = str(raised.value)
    assert "judge model 'pare-test-model'" in message
    assert "read_write" in message and "not in the model-call cache" in message
    assert isinstance(raised.value, UserInputError)
    assert server.count == 0


def test_replay_of_a_missing_file_is_a_clear_error(tmp_path: Path) -> None:
    with pytest.raises(UserInputError, match="does not exist: replay needs a recorded cache"):
        ModelCallCache(tmp_path / "none.sqlite", "replay")


def test_unknown_mode_suggests_the_right_one(tmp_path: Path) -> None:
    with pytest.raises(UserInputError, match="Did you mean 'replay'"):
        ModelCallCache(tmp_path / "c.sqlite", "replya")  # type: ignore[arg-type]


def test_mode_off_never_touches_the_file(
    server: FakeChatServer, make_config: ConfigFactory, tmp_path: Path
) -> None:
    server.push(answer("a"), answer("b"))
    path = tmp_path / "calls.sqlite"
    client = ModelClient(make_config(), role="user", cache=ModelCallCache(path, "off"))
    assert [run(client).text, run(client).text] == ["a", "b"]
    assert not path.exists()


def test_key_covers_what_shapes_the_answer_and_nothing_else() -> None:
    base = ModelConfig(model="m", api_base="http://127.0.0.1:1/v1", api_key_env="A")
    key = cache_key(request_record(base, HELLO, None))

    same = [
        base.model_copy(update={"api_base": "http://127.0.0.1:2/v1", "api_key_env": "B"}),
        base.model_copy(update={"timeout_s": 1.0, "max_retries": 0, "max_concurrency": 1}),
        base.model_copy(update={"prices": Prices(input=1, output=1)}),
    ]
    for config in same:
        assert cache_key(request_record(config, HELLO, None)) == key

    different = [
        request_record(base.model_copy(update={"model": "other"}), HELLO, None),
        request_record(base.model_copy(update={"backend": "litellm"}), HELLO, None),
        request_record(base.model_copy(update={"temperature": 0.7}), HELLO, None),
        request_record(base.model_copy(update={"seed": 1}), HELLO, None),
        request_record(base.model_copy(update={"max_tokens": 10}), HELLO, None),
        request_record(base.model_copy(update={"extra": {"top_p": 0.5}}), HELLO, None),
        request_record(base, [*HELLO, ChatMessage.user("more")], None),
        request_record(base, HELLO, [TOOL]),
    ]
    keys = {cache_key(record) for record in different}
    assert len(keys) == len(different) and key not in keys


def _completion(i: int) -> Completion:
    return Completion(
        text=f"answer {i} é ✓",
        usage=Usage(prompt_tokens=i, completion_tokens=2 * i, cached_tokens=i // 2),
        cost_usd=i / 3 if i % 2 else None,
        latency_s=0.1 * i,
        model="m",
    )


def _writer(path: str, start: int, count: int, go: Any) -> None:
    cache = ModelCallCache(path, "read_write", busy_timeout_s=30)
    go.wait(30)  # both processes write at the same time
    for i in range(start, start + count):
        cache.put(f"key-{i:05d}", _completion(i), request={"backend": "openai", "model": "m"}, role="user")


def test_two_processes_writing_one_file_do_not_corrupt_it(tmp_path: Path) -> None:
    path = str(tmp_path / "shared.sqlite")
    context = multiprocessing.get_context("spawn")
    go = context.Event()
    workers = [context.Process(target=_writer, args=(path, start, 200, go)) for start in (0, 100)]
    for worker in workers:
        worker.start()
    go.set()
    for worker in workers:
        worker.join(timeout=60)
        assert worker.exitcode == 0
    cache = ModelCallCache(path, "replay")
    assert cache.integrity_check() == "ok"
    assert len(cache) == 300  # 0..299; the 100 keys both wrote are stored once
    for i in (0, 99, 100, 199, 299):
        stored = cache.get(f"key-{i:05d}")
        assert stored is not None
        assert stored.model_copy(update={"from_cache": False}) == _completion(i)
    with sqlite3.connect(path) as connection:
        assert connection.execute("PRAGMA journal_mode").fetchone()[0] == "wal"


def test_many_concurrent_tasks_share_one_file(
    server: FakeChatServer, make_config: ConfigFactory, tmp_path: Path
) -> None:
    server.default = answer("same answer", delay_s=0.01)
    cache = ModelCallCache(tmp_path / "calls.sqlite", "read_write")
    ledger = UsageLedger()
    client = ModelClient(make_config(max_concurrency=8), role="user", cache=cache, ledger=ledger)

    async def many() -> list[Completion]:
        async with client:
            calls = [client.complete([ChatMessage.user(f"question {i % 10}")]) for i in range(60)]
            return await asyncio.gather(*calls)

    results = asyncio.run(many())
    assert len(results) == 60
    assert len(cache) == 10
    assert cache.integrity_check() == "ok"
    assert server.count <= 60
    assert ledger.role("user").calls == 60
    # A second pass is served entirely from the file.
    before = server.count
    again = asyncio.run(many())
    assert server.count == before
    assert all(result.from_cache for result in again)
