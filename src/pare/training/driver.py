"""The episode loop stepped from outside: each answer of one actor's model is given by an agent.

:func:`~pare.bench.episode.arun_episode` drives its policies: it asks, they answer. A training environment
needs the inverse, the agent's action handed to ``step``. The driver keeps the loop as it is and runs it as an
asyncio task in which the agent's role is played by PARE's own model-backed actor (:class:`~pare.agents.llm.
LLMAssistant` or :class:`~pare.agents.llm.LLMUser`) over an :class:`ExternalModel`. Each call that actor makes
to its model becomes a :class:`Request`: the conversation the model would be given, and a future the call
waits on. :meth:`EpisodeDriver.answer` resolves it with the agent's text and waits until the loop asks again
or the episode ends. So the prompts, the parsing of the action format, the error texts of malformed answers
and the turn logic are the loop's own; only text crosses. Nothing polls: the driver waits on the request queue
and on the episode task at once.
"""

from __future__ import annotations

import asyncio
import contextlib
from collections.abc import Coroutine, Sequence
from dataclasses import dataclass
from typing import Any, Literal

from pare.agents.models.types import ChatMessage, Completion
from pare.bench.episode import EpisodeResult

ConversationRole = Literal["user", "observe", "execute"]
"""Which conversation a request belongs to: the user's, or the assistant's observe or execute one."""


@dataclass(frozen=True)
class Request:
    """One model call of the agent's actor, waiting for the agent's answer."""

    role: ConversationRole
    messages: tuple[ChatMessage, ...]
    """The whole conversation, as the model is given it."""
    reply: asyncio.Future[str]

    def new_messages(self) -> tuple[ChatMessage, ...]:
        """What the model is given since its last answer: the messages after the last assistant message
        (the whole conversation when it has just started, its system prompt included).
        """
        last = max((i for i, message in enumerate(self.messages) if message.role == "assistant"), default=-1)
        return self.messages[last + 1 :]

    def observation(self) -> str:
        """The text the model reads before answering: the new messages' contents, a blank line apart."""
        return "\n\n".join(message.content or "" for message in self.new_messages())

    def chat(self) -> list[dict[str, Any]]:
        """The conversation in the chat-completions message format."""
        return [message.to_openai() for message in self.messages]


class ExternalModel:
    """A :class:`~pare.agents.llm.ChatModel` whose answers come from outside: each call puts a
    :class:`Request` on ``requests`` and returns the text its future is resolved with.
    """

    name = "external"

    def __init__(self, requests: asyncio.Queue[Request], role: ConversationRole) -> None:
        self.requests = requests
        self.role = role

    async def complete(
        self, messages: Sequence[ChatMessage], tools: Sequence[dict[str, Any]] | None = None
    ) -> Completion:
        """Hand the conversation out and wait for the answer."""
        reply: asyncio.Future[str] = asyncio.get_running_loop().create_future()
        self.requests.put_nowait(Request(self.role, tuple(messages), reply))
        text = await reply
        # An outside agent's tokens and price are its own business: unknown here (None, never 0).
        return Completion(text=text, cost_usd=None, latency_s=0.0, model=self.name)


class EpisodeDriver:
    """One episode played as a task, paused whenever the agent's actor waits for an answer.

    Create it in a running event loop with the queue the agent's :class:`ExternalModel` instances put their
    requests on, and the episode coroutine; then :meth:`next` for the first request, :meth:`answer` for each
    one after. Each returns the next :class:`Request`, or the :class:`~pare.bench.episode.EpisodeResult`
    once the episode is over (an error inside the episode is raised there).
    """

    def __init__(self, requests: asyncio.Queue[Request], episode: Coroutine[Any, Any, EpisodeResult]) -> None:
        self._requests = requests
        self._task: asyncio.Task[EpisodeResult] = asyncio.ensure_future(episode)
        self.pending: Request | None = None
        """The request waiting for :meth:`answer`, if any."""

    async def next(self) -> Request | EpisodeResult:
        """Wait until the agent's actor asks its model, or the episode ends."""
        getter = asyncio.ensure_future(self._requests.get())
        try:
            await asyncio.wait({getter, self._task}, return_when=asyncio.FIRST_COMPLETED)
        finally:
            if not getter.done():
                getter.cancel()
        if getter.done() and not getter.cancelled():
            # While a request waits, the episode cannot end: its actor is waiting for the answer.
            self.pending = getter.result()
            return self.pending
        self.pending = None
        return self._task.result()

    async def answer(self, text: str) -> Request | EpisodeResult:
        """Give the pending request ``text`` as the model's answer; wait for the next request or the end.

        Raises:
            RuntimeError: No request is waiting (the episode is over, or :meth:`next` was not awaited).
        """
        if self.pending is None:
            raise RuntimeError("no model call is waiting for an answer: the episode is over or not started")
        pending, self.pending = self.pending, None
        pending.reply.set_result(text)
        return await self.next()

    async def aclose(self) -> None:
        """Stop the episode if it is still being played."""
        if self._task.done():
            if not self._task.cancelled():
                self._task.exception()  # retrieved: an episode that failed has said so from step already
            return
        self._task.cancel()
        with contextlib.suppress(asyncio.CancelledError):
            await self._task
