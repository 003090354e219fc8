"""No secret value reaches any file of a run: not the API key a provider echoes back in its errors, not
secret-looking ``extra`` request parameters (in the manifest's identity and config, or in the cache)."""

from __future__ import annotations

import base64
import json
import sqlite3
from pathlib import Path
from typing import Any

from pare.cli import main
from pare.testing import ChatServer, Reply, failure, proactive_play
from tests.hardening.conftest import KEY_VARIABLE

KEY = "sk-pare-hardening-test"  # the conftest's key
EXTRA_KEY = "sk-extra-0123456789abcdef"
BEARER = "tok-bearer-fedcba9876543210"


def run_argv(output: Path, scenario: Path, server: ChatServer, *extra: str) -> list[str]:
    argv = ["run", "--output", str(output), "--no-progress", "--runs", "1", "--scenario-path", str(scenario)]
    argv += ["--assistant-model", "a", "--assistant-endpoint", server.base_url]
    argv += ["--user-model", "u", "--user-endpoint", server.base_url]
    extras = json.dumps({"session_token": EXTRA_KEY, "metadata": {"authorization": f"Bearer {BEARER}"}})
    for role in ("user", "assistant"):
        argv += [
            "--set",
            f"models.{role}.api_key_env={KEY_VARIABLE}",
            "--set",
            f"models.{role}.extra={extras}",
        ]
        argv += ["--set", f"models.{role}.retry_initial_s=0", "--set", f"models.{role}.max_retries=1"]
    return [*argv, "--set", "episode_retries=0", *extra]


def every_file(folder: Path) -> str:
    return "\n".join(
        path.read_bytes().decode("utf-8", "replace") for path in folder.rglob("*") if path.is_file()
    )


def test_secret_extras_stay_out_of_the_manifest_and_the_cache(tmp_path: Path, example_scenario: Path) -> None:
    with ChatServer(proactive_play()) as server:
        output = tmp_path / "run"
        assert main(run_argv(output, example_scenario, server)) == 0
        sent = json.dumps(server.requests)
    assert EXTRA_KEY in sent  # the provider did get them
    written = every_file(output)
    for secret in (KEY, EXTRA_KEY, BEARER):
        assert secret not in written
    manifest = json.loads((output / "manifest.json").read_text(encoding="utf-8"))
    assert manifest["identity"]["models"]["user"]["extra"]["session_token"] == "***"


def test_a_provider_that_echoes_the_key_does_not_leak_it(tmp_path: Path, example_scenario: Path) -> None:
    def echo(request: dict[str, Any]) -> Reply:
        return failure(503, f"overloaded; your request used key {KEY} and {EXTRA_KEY} (Bearer {BEARER})")

    with ChatServer(echo) as server:
        output = tmp_path / "run"
        assert main(run_argv(output, example_scenario, server)) == 1  # missing coverage
    record = json.loads((output / "episodes.jsonl").read_text(encoding="utf-8").splitlines()[0])
    assert record["failure"]["kind"] == "provider_unavailable"
    assert "overloaded; your request used key ***" in record["failure"]["message"]
    written = every_file(output)
    for secret in (KEY, EXTRA_KEY, BEARER):
        assert secret not in written


HEADER_SECRETS = {
    "Helicone-Auth": "Bearer sk-helicone-5f0e1d2c3b4a5968",
    "Cookie": "session=c00kie-a1b2c3d4e5f60718",
    "X-Portkey-Virtual-Key": "pk-virtual-99aa88bb77cc66dd",
}


def header_argv(output: Path, scenario: Path, server: ChatServer) -> list[str]:
    argv = ["run", "--output", str(output), "--no-progress", "--runs", "1", "--scenario-path", str(scenario)]
    argv += ["--assistant-model", "a", "--assistant-endpoint", server.base_url]
    argv += ["--user-model", "u", "--user-endpoint", server.base_url]
    extras = json.dumps({"extra_headers": HEADER_SECRETS})
    for role in ("user", "assistant"):
        argv += [
            "--set",
            f"models.{role}.api_key_env={KEY_VARIABLE}",
            "--set",
            f"models.{role}.extra={extras}",
        ]
        argv += ["--set", f"models.{role}.retry_initial_s=0", "--set", f"models.{role}.max_retries=1"]
    return [*argv, "--set", "episode_retries=0"]


def header_secret_texts() -> list[str]:
    """Each header's credential: the whole value and its token (what a leak would show)."""
    return [part for value in HEADER_SECRETS.values() for part in (value, value.split()[-1])]


def test_header_values_are_sent_as_headers_and_stored_nowhere(tmp_path: Path, example_scenario: Path) -> None:
    with ChatServer(proactive_play()) as server:
        output = tmp_path / "run"
        assert main(header_argv(output, example_scenario, server)) == 0
        received = server.headers
        bodies = json.dumps(server.requests)
    assert received and received[0]["helicone-auth"] == HEADER_SECRETS["Helicone-Auth"]
    assert "extra_headers" not in bodies  # headers travel as headers, not as a body field
    written = every_file(output)
    for secret in header_secret_texts():
        assert secret not in written
    manifest = json.loads((output / "manifest.json").read_text(encoding="utf-8"))
    stored = manifest["config"]["models"]["user"]["extra"]["extra_headers"]
    assert stored == dict.fromkeys(HEADER_SECRETS, "***")
    cache = (
        sqlite3.connect(output / "model_calls.sqlite") if (output / "model_calls.sqlite").exists() else None
    )
    if cache is not None:
        requests = " ".join(row[0] for row in cache.execute("SELECT request FROM completions"))
        cache.close()
        assert requests and all(secret not in requests for secret in header_secret_texts())


def test_echoes_of_header_secrets_in_any_form_are_cut(tmp_path: Path, example_scenario: Path) -> None:
    token = HEADER_SECRETS["Helicone-Auth"].split()[-1]
    basic = base64.b64encode(f"user:{token}".encode()).decode()

    def echo(request: dict[str, Any]) -> Reply:
        return failure(
            503,
            f"refused {token.lower()} / {token.upper()} / basic {basic} / "
            f"key starting {token[:12]}... / {HEADER_SECRETS['Cookie']}",
        )

    with ChatServer(echo) as server:
        output = tmp_path / "run"
        assert main(header_argv(output, example_scenario, server)) == 1  # missing coverage
    record = json.loads((output / "episodes.jsonl").read_text(encoding="utf-8").splitlines()[0])
    message = record["failure"]["message"]
    assert "refused ***" in message
    written = every_file(output).lower()
    for leaked in (token, basic[8:], token[:12], HEADER_SECRETS["Cookie"].split("=")[1]):
        assert leaked.lower() not in written
