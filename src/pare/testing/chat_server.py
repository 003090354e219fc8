"""A small OpenAI-compatible chat-completions server on 127.0.0.1, and a responder that plays PARE's roles.

:class:`ChatServer` serves ``POST /v1/chat/completions`` (stdlib :class:`~http.server.ThreadingHTTPServer`,
one daemon thread per request, a listen backlog of 256 so bursts of concurrent episodes are not dropped).
Each request body is handed to a *responder*, ``responder(body) -> Reply``, whose :class:`Reply` (status,
JSON body, headers) is sent back after ``delay_s`` seconds (a stand-in for a model's latency). The server
records, thread-safely, how many requests it received, how many were in flight at once (the most), and
every request body and header set (header names in lower case), so a test can check what was sent, and
how often. :func:`completion` and :func:`failure` build the usual replies.

:func:`proactive_play` is a ready responder that plays a plausible game for every role of PARE, in the
paper's text action format (written with :func:`pare.agents.actions.format_action`):

* the **user** accepts the assistant's pending proposal when the latest screen in its conversation offers
  ``accept_proposal``, and otherwise waits (``wait``);
* the assistant in **observe** mode proposes :data:`PROPOSAL` through ``agent_ui__send_message_to_user`` on
  the first call of its conversation and waits (``system__wait``) on every later one;
* the assistant in **execute** mode sends its report (:data:`REPORT`, ``agent_ui__send_message_to_user``)
  at once.

It decides from the request alone (the role from the system prompt, the rest from the conversation), keeps
no state between requests, and so serves any number of concurrent episodes, deterministically.

:func:`thinking` makes any responder a thinking model's: each answer comes with reasoning that drafts an
``Action:`` of its own, inline as a think block or in the message's ``reasoning_content`` field.
"""

from __future__ import annotations

import dataclasses
import functools
import json
import re
import threading
import time
import traceback
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer
from typing import Any, Literal

from pare.agents.actions import format_action
from pare.agents.policy import ASSISTANT_WAIT, SEND_MESSAGE, WAIT
from pare.agents.prompts import TEMPLATES

__all__ = [
    "PROPOSAL",
    "REPORT",
    "ChatServer",
    "Reply",
    "Responder",
    "completion",
    "conversation_role",
    "failure",
    "proactive_play",
    "thinking",
]

ChatRole = Literal["user", "observe", "execute"]
"""The model roles whose conversations :func:`conversation_role` tells apart."""

ACCEPT = "accept_proposal"
"""The user's tool for accepting the pending proposal (offered only while one is pending)."""

PROPOSAL = (
    "I can take care of what just came in for you: I will handle it exactly as it asks and tell you "
    "when it is done. Shall I go ahead?"
)
"""What :func:`proactive_play`'s assistant proposes, once per episode."""

REPORT = "Done: I took care of it as proposed."
"""What :func:`proactive_play`'s assistant reports in execute mode."""


# -- replies ------------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class Reply:
    """One HTTP answer: its status, its JSON body and extra headers; ``raw``, when given, is sent as the
    body instead of ``body`` (for tests of providers whose answers are truncated, empty or not UTF-8).
    """

    status: int = 200
    body: dict[str, Any] = field(default_factory=dict)
    headers: dict[str, str] = field(default_factory=dict)
    raw: bytes | None = None


Responder = Callable[[dict[str, Any]], Reply]
"""Answers one chat-completions request, given its JSON body (``model``, ``messages``, ...)."""


def completion(
    text: str,
    prompt_tokens: int = 100,
    completion_tokens: int = 20,
    *,
    model: str = "pare-test-model",
    reasoning: str | None = None,
) -> Reply:
    """A successful chat completion whose message is ``text``, reporting the given token usage;
    ``reasoning``, when given, is the message's ``reasoning_content`` (a thinking model's, as vLLM returns
    it with a reasoning parser).
    """
    message: dict[str, Any] = {"role": "assistant", "content": text}
    if reasoning is not None:
        message["reasoning_content"] = reasoning
    return Reply(
        200,
        {
            "id": "chatcmpl-pare-testing",
            "object": "chat.completion",
            "created": 1_700_000_000,
            "model": model,
            "choices": [{"index": 0, "message": message, "finish_reason": "stop"}],
            "usage": {
                "prompt_tokens": prompt_tokens,
                "completion_tokens": completion_tokens,
                "total_tokens": prompt_tokens + completion_tokens,
                "prompt_tokens_details": {"cached_tokens": 0},
            },
        },
    )


def failure(
    status: int,
    message: str,
    *,
    type_: str | None = None,
    code: str | None = None,
    headers: Mapping[str, str] | None = None,
) -> Reply:
    """An error in the OpenAI format (``{"error": {"message", "type", "param", "code"}}``).

    ``type_`` defaults to ``server_error`` for 5xx statuses and ``invalid_request_error`` otherwise.
    """
    kind = type_ or ("server_error" if status >= 500 else "invalid_request_error")
    body = {"error": {"message": message, "type": kind, "param": None, "code": code}}
    return Reply(status, body, dict(headers or {}))


# -- the server ---------------------------------------------------------------------------------------------
class _HTTPServer(ThreadingHTTPServer):
    daemon_threads = True
    block_on_close = False
    request_queue_size = 256  # the default backlog of 5 drops connections when many episodes call at once


class ChatServer:
    """An OpenAI-compatible chat-completions endpoint on 127.0.0.1 that answers through ``responder``.

    Use it as a context manager (or call :meth:`start` and :meth:`stop`); :attr:`base_url` (ending in
    ``/v1``) is what a model configuration's ``api_base`` takes. Every answer waits ``delay_s`` seconds
    first. ``responder`` and ``delay_s`` may be replaced while the server runs (a provider that recovers).
    A responder that raises is answered with status 400 and its traceback, so the run stops with the
    error in view instead of retrying; the exceptions are kept in :attr:`errors`.
    """

    def __init__(self, responder: Responder, *, delay_s: float = 0.0) -> None:
        self.responder = responder
        self.delay_s = delay_s
        self._lock = threading.Lock()
        self._requests: list[dict[str, Any]] = []
        self._headers: list[dict[str, str]] = []
        self._errors: list[BaseException] = []
        self._in_flight = 0
        self._max_in_flight = 0
        self._httpd: _HTTPServer | None = None
        self._thread: threading.Thread | None = None

    # -- life cycle --------------------------------------------------------------------------------------
    def start(self) -> ChatServer:
        """Listen on a free port of 127.0.0.1 and serve in a background thread; returns the server."""
        if self._httpd is not None:
            raise RuntimeError("the chat server is already running")
        self._httpd = _HTTPServer(("127.0.0.1", 0), self._handler_class())
        self._thread = threading.Thread(
            target=self._httpd.serve_forever,
            kwargs={"poll_interval": 0.01},
            name=f"pare-chat-server-{self.port}",
            daemon=True,
        )
        self._thread.start()
        return self

    def stop(self) -> None:
        """Stop serving and release the port (requests still being answered finish on their own)."""
        httpd, thread = self._httpd, self._thread
        self._httpd = self._thread = None
        if httpd is not None:
            httpd.shutdown()
            httpd.server_close()
        if thread is not None:
            thread.join(timeout=5)

    def __enter__(self) -> ChatServer:
        return self.start()

    def __exit__(self, *exc_info: object) -> None:
        self.stop()

    # -- where and what ----------------------------------------------------------------------------------
    @property
    def port(self) -> int:
        """The port the server listens on (only while it runs)."""
        if self._httpd is None:
            raise RuntimeError("the chat server is not running; call start() first")
        return int(self._httpd.server_address[1])

    @property
    def base_url(self) -> str:
        """The endpoint's base URL, ``http://127.0.0.1:<port>/v1`` (only while it runs)."""
        return f"http://127.0.0.1:{self.port}/v1"

    @property
    def request_count(self) -> int:
        """Requests received so far (every POST, answered or not)."""
        with self._lock:
            return len(self._requests)

    @property
    def in_flight(self) -> int:
        """Requests being answered now."""
        with self._lock:
            return self._in_flight

    @property
    def max_in_flight(self) -> int:
        """The most requests that were being answered at the same time."""
        with self._lock:
            return self._max_in_flight

    @property
    def requests(self) -> list[dict[str, Any]]:
        """The JSON bodies received, in order of arrival (a copy)."""
        with self._lock:
            return list(self._requests)

    @property
    def headers(self) -> list[dict[str, str]]:
        """The headers of each request received (names in lower case), in order of arrival (a copy)."""
        with self._lock:
            return [dict(headers) for headers in self._headers]

    @property
    def errors(self) -> list[BaseException]:
        """Exceptions the responder raised (each was answered with status 400)."""
        with self._lock:
            return list(self._errors)

    def reset(self) -> None:
        """Forget the requests, headers, errors and the in-flight maximum recorded so far."""
        with self._lock:
            self._requests.clear()
            self._headers.clear()
            self._errors.clear()
            self._max_in_flight = self._in_flight

    # -- answering ---------------------------------------------------------------------------------------
    def _answer(self, path: str, headers: dict[str, str], raw: bytes) -> Reply:
        try:
            body = json.loads(raw or b"{}")
        except (json.JSONDecodeError, UnicodeDecodeError) as error:
            return failure(400, f"the request body is not JSON: {error}")
        if not isinstance(body, dict):
            return failure(400, "the request body must be a JSON object")
        with self._lock:
            self._requests.append(body)
            self._headers.append(headers)
        if not path.split("?", 1)[0].rstrip("/").endswith("/chat/completions"):
            return failure(404, f"no route {path}: this server only answers POST /v1/chat/completions")
        try:
            return self.responder(body)
        except Exception as error:
            with self._lock:
                self._errors.append(error)
            detail = "".join(traceback.format_exception(error, limit=-4)).strip()
            return failure(400, f"the test server's responder failed: {detail}", code="responder_error")

    def _handler_class(self) -> type[BaseHTTPRequestHandler]:
        server = self

        class Handler(BaseHTTPRequestHandler):
            protocol_version = "HTTP/1.1"  # keep connections alive, as real model servers do
            # The headers and the body go out as two writes: with Nagle's algorithm on, the body waits for
            # the client's delayed ACK of the headers (about 40 ms per call on Linux).
            disable_nagle_algorithm = True

            def log_message(self, format: str, *args: Any) -> None:
                """Stay quiet."""

            def do_POST(self) -> None:
                with server._lock:
                    server._in_flight += 1
                    server._max_in_flight = max(server._max_in_flight, server._in_flight)
                try:
                    length = int(self.headers.get("Content-Length") or 0)
                    raw = self.rfile.read(length)
                    headers = {name.lower(): value for name, value in self.headers.items()}
                    reply = server._answer(self.path, headers, raw)
                    if server.delay_s > 0:
                        time.sleep(server.delay_s)
                    self._send(reply)
                except (BrokenPipeError, ConnectionResetError):
                    pass  # the client gave up (a timeout or a cancelled run)
                finally:
                    with server._lock:
                        server._in_flight -= 1

            def do_GET(self) -> None:
                self._send(failure(404, f"no route GET {self.path}"))

            def _send(self, reply: Reply) -> None:
                payload = reply.raw if reply.raw is not None else json.dumps(reply.body).encode("utf-8")
                self.send_response(reply.status)
                self.send_header("Content-Type", "application/json")
                self.send_header("Content-Length", str(len(payload)))
                for name, value in reply.headers.items():
                    self.send_header(name, value)
                self.end_headers()
                self.wfile.write(payload)

        return Handler


# -- a responder that plays the game ------------------------------------------------------------------------
@functools.cache
def _role_openings() -> dict[ChatRole, str]:
    """The first line of each role's system prompt template: static text that starts the rendered prompt."""
    templates: dict[ChatRole, str] = {"user": "user.j2", "observe": "observe.j2", "execute": "execute.j2"}
    openings: dict[ChatRole, str] = {}
    for role, name in templates.items():
        first = (TEMPLATES / name).read_text(encoding="utf-8").lstrip().split("\n", 1)[0].strip()
        if not first or "{" in first:
            raise RuntimeError(f"the first line of {name} is not static text, so it cannot name the role")
        openings[role] = first
    if len(set(openings.values())) != len(openings):
        raise RuntimeError("two role templates start alike, so their conversations cannot be told apart")
    return openings


def conversation_role(messages: Sequence[Mapping[str, Any]]) -> ChatRole | None:
    """Which role's conversation ``messages`` is (OpenAI chat format), from its system prompt; ``None``
    when it is none of PARE's user, observe and execute prompts.
    """
    system = next((m for m in messages if m.get("role") == "system"), None)
    content = system.get("content") if system is not None else None
    if not isinstance(content, str):
        return None
    text = content.lstrip()
    for role, opening in _role_openings().items():
        if text.startswith(opening):
            return role
    return None


def _text(message: Mapping[str, Any]) -> str:
    content = message.get("content")
    if isinstance(content, str):
        return content
    if isinstance(content, list):  # content parts
        return "\n".join(str(part.get("text", "")) for part in content if isinstance(part, dict))
    return ""


def _offered(body: Mapping[str, Any], latest: str, tool: str) -> bool:
    """Whether the latest observation lists ``tool`` among the tools available now (or, with native tool
    calling, the request's tools include it).
    """
    if re.search(rf"^- {re.escape(tool)}\(", latest, re.MULTILINE):
        return True
    for schema in body.get("tools") or ():
        if isinstance(schema, dict) and (schema.get("function") or {}).get("name") == tool:
            return True
    return False


def proactive_play(*, proposal: str = PROPOSAL, report: str = REPORT) -> Responder:
    """A responder that plays every PARE role plausibly, from the request alone (see the module docstring).

    The user accepts a pending proposal when its latest screen offers ``accept_proposal`` and otherwise
    waits; observe mode proposes ``proposal`` on its conversation's first call and waits afterwards;
    execute mode reports ``report`` at once. Answers are in the paper's text format; the usage reported is
    derived from the request (prompt tokens about a quarter of its characters) and the answer. A request
    from no known role is answered with status 400, which stops a run with the reason in view.
    """

    def respond(body: dict[str, Any]) -> Reply:
        messages = [m for m in body.get("messages") or () if isinstance(m, dict)]
        role = conversation_role(messages)
        if role is None:
            return failure(
                400,
                "proactive_play cannot tell the role of this conversation: its system prompt is not PARE's "
                "user, observe or execute prompt",
            )
        if role == "user":
            observed = [m for m in messages if m.get("role") in ("user", "tool")]
            latest = _text(observed[-1]) if observed else ""
            if _offered(body, latest, ACCEPT):
                text = format_action(
                    ACCEPT, {"reason": "Yes, please go ahead."}, "The assistant offers to help; I accept."
                )
            else:
                text = format_action(WAIT, {}, "Nothing needs me right now; I wait.")
        elif role == "observe":
            if any(m.get("role") == "assistant" for m in messages):
                text = format_action(ASSISTANT_WAIT, {}, "I already offered my help; I keep watching.")
            else:
                text = format_action(SEND_MESSAGE, {"content": proposal}, "I can help with this; I propose.")
        else:
            text = format_action(SEND_MESSAGE, {"content": report}, "The task is done; I report to the user.")
        prompt_tokens = max(1, sum(len(_text(m)) for m in messages) // 4)
        model = body.get("model")
        return completion(
            text,
            prompt_tokens,
            max(1, len(text) // 4),
            model=model if isinstance(model, str) and model else "pare-test-model",
        )

    return respond


# -- thinking models ----------------------------------------------------------------------------------------
ThinkingStyle = Literal["inline", "unopened", "field"]
"""How :func:`thinking` returns the reasoning: ``inline``, a ``<think> ... </think>`` block before the
answer; ``unopened``, the same without its opening tag (the chat template put ``<think>`` in the prompt,
so the text starts mid-thought); ``field``, the message's ``reasoning_content``."""

THINKING = (
    "Let me work out what to do. A first draft of my answer:\n"
    "Action:\n"
    '{"action": "draft_from_thinking", "action_input": {"note": "only a draft"}}\n'
    "No, let me look at the conversation again before I answer."
)
"""The reasoning :func:`thinking` adds: it drafts an ``Action:`` with a JSON object, which must never be
read as the answer (``draft_from_thinking`` is no tool of PARE's, so a step that took it would fail)."""


def thinking(responder: Responder, *, style: ThinkingStyle = "inline", thought: str = THINKING) -> Responder:
    """``responder`` as a thinking model: every successful answer comes with ``thought`` as its reasoning,
    returned in ``style`` (see :data:`ThinkingStyle`); its tokens (a quarter of its characters) are added
    to the reported completion tokens, as servers count them. Other replies pass unchanged.
    """
    if style not in ("inline", "unopened", "field"):
        raise ValueError(f"unknown thinking style {style!r}: use 'inline', 'unopened' or 'field'")

    def respond(body: dict[str, Any]) -> Reply:
        reply = responder(body)
        choices = reply.body.get("choices")
        if reply.status != 200 or reply.raw is not None or not isinstance(choices, list):
            return reply
        answer = json.loads(json.dumps(reply.body))  # a deep copy: the responder may reuse its bodies
        for choice in answer["choices"]:
            message = choice.get("message") if isinstance(choice, dict) else None
            if not isinstance(message, dict):
                continue
            content = message.get("content") or ""
            if style == "field":
                message["reasoning_content"] = thought
            elif style == "inline":
                message["content"] = f"<think>\n{thought}\n</think>\n\n{content}"
            else:
                message["content"] = f"{thought}\n</think>\n\n{content}"
        usage = answer.get("usage")
        if isinstance(usage, dict):
            extra = max(1, len(thought) // 4)
            for name in ("completion_tokens", "total_tokens"):
                if isinstance(usage.get(name), int):
                    usage[name] += extra
        return dataclasses.replace(reply, body=answer)

    return respond
