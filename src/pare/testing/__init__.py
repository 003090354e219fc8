"""Test doubles that ship with PARE, for tests, benchmarks and offline dry runs of the model-backed path.

* :class:`ChatServer` — a small OpenAI-compatible chat-completions server on 127.0.0.1 that answers
  through a *responder* and records what it was sent;
* :func:`proactive_play` — a ready responder that plays the user and the assistant (observe and execute)
  plausibly and deterministically, so ``pare run`` can go end to end without a real model;
* :func:`thinking` — wraps a responder so that it answers like a thinking model (reasoning inline as a
  think block or in a separate field).
* :class:`RateLimited` — wraps a responder to answer at most so many requests a second and 429 with
  Retry-After beyond that, as a rate-limiting provider does:

.. code-block:: python

    from pare.testing import ChatServer, proactive_play

    with ChatServer(proactive_play(), delay_s=0.2) as server:
        ...  # point models.user / models.assistant api_base at server.base_url

Provider profiles (:mod:`pare.testing.providers`) wrap any responder to answer as the major providers do:
OpenAI's reasoning models' parameter refusals (:func:`openai_reasoning`), rate limits, tool-call-only
answers, cached prompt tokens, context-length errors, and Anthropic's Messages API
(:class:`AnthropicChatServer`).
"""

from pare.testing.chat_server import (
    PROPOSAL,
    REPORT,
    ChatServer,
    Reply,
    Responder,
    completion,
    conversation_role,
    failure,
    proactive_play,
    thinking,
)
from pare.testing.providers import (
    PROFILES,
    AnthropicChatServer,
    anthropic_messages,
    cached_prompts,
    context_limit,
    openai_reasoning,
    rate_limited,
    tool_calls_only,
)
from pare.testing.rate_limit import RateLimited

__all__ = [
    "PROFILES",
    "PROPOSAL",
    "REPORT",
    "AnthropicChatServer",
    "ChatServer",
    "RateLimited",
    "Reply",
    "Responder",
    "anthropic_messages",
    "cached_prompts",
    "completion",
    "context_limit",
    "conversation_role",
    "failure",
    "openai_reasoning",
    "proactive_play",
    "rate_limited",
    "thinking",
    "tool_calls_only",
]
