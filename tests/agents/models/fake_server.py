"""A tiny OpenAI-compatible chat server on 127.0.0.1 that answers from a script and records requests."""

from __future__ import annotations

import json
import threading
import time
from collections import deque
from dataclasses import dataclass, field
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer
from typing import Any


@dataclass
class Reply:
    status: int = 200
    body: dict[str, Any] = field(default_factory=dict)
    headers: dict[str, str] = field(default_factory=dict)
    delay_s: float = 0.0


def answer(
    text: str = "Hello.",
    *,
    prompt_tokens: int = 1000,
    completion_tokens: int = 100,
    cached_tokens: int = 0,
    model: str = "pare-test-model",
    tool_calls: list[dict[str, Any]] | None = None,
    usage: bool = True,
    delay_s: float = 0.0,
) -> Reply:
    message: dict[str, Any] = {"role": "assistant", "content": text}
    if tool_calls:
        message["tool_calls"] = tool_calls
    body: dict[str, Any] = {
        "id": "chatcmpl-test",
        "object": "chat.completion",
        "created": 1_700_000_000,
        "model": model,
        "choices": [
            {"index": 0, "message": message, "finish_reason": "tool_calls" if tool_calls else "stop"}
        ],
    }
    if usage:
        body["usage"] = {
            "prompt_tokens": prompt_tokens,
            "completion_tokens": completion_tokens,
            "total_tokens": prompt_tokens + completion_tokens,
            "prompt_tokens_details": {"cached_tokens": cached_tokens},
        }
    return Reply(200, body, delay_s=delay_s)


def tool_call(call_id: str, name: str, arguments: dict[str, Any]) -> dict[str, Any]:
    return {"id": call_id, "type": "function", "function": {"name": name, "arguments": json.dumps(arguments)}}


def error(
    status: int,
    message: str,
    *,
    type_: str = "invalid_request_error",
    code: str | None = None,
    headers: dict[str, str] | None = None,
) -> Reply:
    body = {"error": {"message": message, "type": type_, "param": None, "code": code}}
    return Reply(status, body, headers=dict(headers or {}))


RATE_LIMITED = error(429, "Rate limit reached, slow down", type_="requests", code="rate_limit_exceeded")
SERVER_ERROR = error(500, "The server had an error while processing your request.", type_="server_error")
OVERLOADED = error(503, "The engine is currently overloaded, please try again later.", type_="server_error")
BAD_KEY = error(401, "Incorrect API key provided: sk-test***.", code="invalid_api_key")
NO_MODEL = error(404, "The model `no-such-model` does not exist.", code="model_not_found")
NO_ACCESS = error(403, "You are not allowed to use this model.", type_="permission_error")
TOO_LONG = error(
    400,
    "This model's maximum context length is 8192 tokens. However, your messages resulted in 9000 tokens.",
    code="context_length_exceeded",
)
BAD_PARAM = error(400, "Unrecognized request argument supplied: frobnicate", code=None)
NO_QUOTA = error(
    429, "You exceeded your current quota.", type_="insufficient_quota", code="insufficient_quota"
)


class _Server(ThreadingHTTPServer):
    daemon_threads = True
    block_on_close = False
    request_queue_size = 128  # the default backlog of 5 drops connections under concurrency tests


class FakeChatServer:
    """Serves POST /v1/chat/completions from a queue of replies; thread-safe; counts requests in flight."""

    def __init__(self) -> None:
        self.script: deque[Reply] = deque()
        self.default: Reply | None = None
        self.requests: list[dict[str, Any]] = []
        self.headers: list[dict[str, str]] = []
        self.in_flight = 0
        self.max_in_flight = 0
        self._lock = threading.Lock()
        server = self

        class Handler(BaseHTTPRequestHandler):
            def log_message(self, format: str, *args: Any) -> None:  # quiet
                pass

            def do_POST(self) -> None:
                length = int(self.headers.get("Content-Length", "0"))
                body = json.loads(self.rfile.read(length) or b"{}")
                with server._lock:
                    server.requests.append({"path": self.path, **body})
                    server.headers.append({k.lower(): v for k, v in self.headers.items()})
                    server.in_flight += 1
                    server.max_in_flight = max(server.max_in_flight, server.in_flight)
                    if not self.path.rstrip("/").endswith("/chat/completions"):
                        reply = error(404, f"no route {self.path}")
                    elif server.script:
                        reply = server.script.popleft()
                    elif server.default is not None:
                        reply = server.default
                    else:
                        reply = error(500, "the test's script of replies is empty", type_="server_error")
                try:
                    if reply.delay_s:
                        time.sleep(reply.delay_s)
                    payload = json.dumps(reply.body).encode()
                    self.send_response(reply.status)
                    self.send_header("Content-Type", "application/json")
                    self.send_header("Content-Length", str(len(payload)))
                    for name, value in reply.headers.items():
                        self.send_header(name, value)
                    self.end_headers()
                    self.wfile.write(payload)
                except (BrokenPipeError, ConnectionResetError):
                    pass  # the client gave up (a timeout test)
                finally:
                    with server._lock:
                        server.in_flight -= 1

        self.httpd = _Server(("127.0.0.1", 0), Handler)
        self.port = self.httpd.server_address[1]
        self.base_url = f"http://127.0.0.1:{self.port}/v1"
        self._thread = threading.Thread(target=self.httpd.serve_forever, kwargs={"poll_interval": 0.01})
        self._thread.daemon = True

    def start(self) -> FakeChatServer:
        self._thread.start()
        return self

    def stop(self) -> None:
        self.httpd.shutdown()
        self.httpd.server_close()
        self._thread.join(timeout=5)

    def push(self, *replies: Reply) -> None:
        with self._lock:
            self.script.extend(replies)

    @property
    def count(self) -> int:
        with self._lock:
            return len(self.requests)
