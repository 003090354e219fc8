"""Test doubles that ship with PARE, for tests, benchmarks and offline dry runs of the model-backed path.

* :class:`ChatServer` — a small OpenAI-compatible chat-completions server on 127.0.0.1 that answers
  through a *responder* and records what it was sent;
* :func:`proactive_play` — a ready responder that plays the user and the assistant (observe and execute)
  plausibly and deterministically, so ``pare run`` can go end to end without a real model;
* :class:`RateLimited` — wraps a responder to answer at most so many requests a second and 429 with
  Retry-After beyond that, as a rate-limiting provider does:

.. code-block:: python

    from pare.testing import ChatServer, proactive_play

    with ChatServer(proactive_play(), delay_s=0.2) as server:
        ...  # point models.user / models.assistant api_base at server.base_url
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
)
from pare.testing.rate_limit import RateLimited

__all__ = [
    "PROPOSAL",
    "REPORT",
    "ChatServer",
    "RateLimited",
    "Reply",
    "Responder",
    "completion",
    "conversation_role",
    "failure",
    "proactive_play",
]
