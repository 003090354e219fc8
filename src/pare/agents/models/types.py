"""The messages sent to a model and the completion that comes back; all of it JSON-serialisable."""

from __future__ import annotations

from typing import Any, Literal

from pydantic import BaseModel, ConfigDict, Field, model_validator

Role = Literal["system", "user", "assistant", "tool"]


class ToolCall(BaseModel):
    """A function call the model asked for through native tool calling."""

    model_config = ConfigDict(extra="forbid", frozen=True)

    id: str = Field(description="The provider's id for the call; a tool message answers it by this id.")
    name: str
    arguments: str = Field(
        description="The arguments as the JSON text the model wrote (may be invalid JSON)."
    )

    def to_openai(self) -> dict[str, Any]:
        """Return the call in the OpenAI chat format."""
        return {
            "id": self.id,
            "type": "function",
            "function": {"name": self.name, "arguments": self.arguments},
        }


class ChatMessage(BaseModel):
    """One message of a conversation, in the OpenAI chat format's terms."""

    model_config = ConfigDict(extra="forbid", frozen=True)

    role: Role
    content: str | None = None
    tool_calls: tuple[ToolCall, ...] | None = Field(default=None, description="Only on assistant messages.")
    tool_call_id: str | None = Field(default=None, description="Only on tool messages: the call answered.")
    name: str | None = None

    @model_validator(mode="after")
    def _consistent(self) -> ChatMessage:
        if self.role == "tool" and not self.tool_call_id:
            raise ValueError("a tool message needs the tool_call_id of the call it answers")
        if self.tool_calls and self.role != "assistant":
            raise ValueError("only assistant messages carry tool_calls")
        if self.content is None and not self.tool_calls:
            raise ValueError(f"a {self.role} message needs content")
        return self

    @classmethod
    def system(cls, content: str) -> ChatMessage:
        """Return a system message."""
        return cls(role="system", content=content)

    @classmethod
    def user(cls, content: str) -> ChatMessage:
        """Return a user message."""
        return cls(role="user", content=content)

    @classmethod
    def assistant(cls, content: str | None, tool_calls: tuple[ToolCall, ...] | None = None) -> ChatMessage:
        """Return an assistant message, optionally with the tool calls it made."""
        return cls(role="assistant", content=content, tool_calls=tool_calls or None)

    @classmethod
    def tool(cls, tool_call_id: str, content: str, name: str | None = None) -> ChatMessage:
        """Return a tool message answering the call ``tool_call_id``."""
        return cls(role="tool", content=content, tool_call_id=tool_call_id, name=name)

    def to_openai(self) -> dict[str, Any]:
        """Return the message in the OpenAI chat format (fields that are unset are left out)."""
        message: dict[str, Any] = {"role": self.role, "content": self.content}
        if self.tool_calls:
            message["tool_calls"] = [call.to_openai() for call in self.tool_calls]
        if self.tool_call_id is not None:
            message["tool_call_id"] = self.tool_call_id
        if self.name is not None:
            message["name"] = self.name
        return message


class Usage(BaseModel):
    """Tokens of one call (or of many, summed). ``cached_tokens`` are part of ``prompt_tokens``."""

    model_config = ConfigDict(extra="forbid", frozen=True)

    prompt_tokens: int = Field(default=0, ge=0)
    completion_tokens: int = Field(default=0, ge=0)
    cached_tokens: int = Field(default=0, ge=0, description="Prompt tokens served from the provider's cache.")

    @property
    def total_tokens(self) -> int:
        """Prompt plus completion tokens."""
        return self.prompt_tokens + self.completion_tokens


class Completion(BaseModel):
    """What one model call returned, with what it used and cost."""

    model_config = ConfigDict(extra="forbid", frozen=True)

    text: str = Field(description="The message's text ('' when the model only called tools).")
    tool_calls: tuple[ToolCall, ...] = ()
    usage: Usage = Field(default_factory=Usage)
    cost_usd: float | None = Field(description="Price of the call in USD; None when unknown, never 0 for it.")
    latency_s: float = Field(ge=0.0, description="Seconds the successful request took (retries excluded).")
    model: str = Field(description="The model that answered, as the provider named it.")
    finish_reason: str | None = None
    reasoning: str | None = Field(
        default=None,
        description="A thinking model's reasoning, kept apart from ``text`` (which holds the answer only); "
        "its tokens count in ``usage.completion_tokens``.",
    )
    from_cache: bool = Field(default=False, description="Replayed from the record/replay cache, not called.")
    cut_from: int | None = Field(
        default=None,
        ge=0,
        description="The answer's length in characters (text and tool-call arguments) when it was longer "
        "than its role's ``max_answer_chars``: the text is then cut to that many and the tool calls "
        "dropped, and the actor treats the answer as a format error.",
    )

    def message(self) -> ChatMessage:
        """Return the assistant message to append to the conversation.

        It holds the answer without the reasoning: providers expect only the answer in earlier turns
        (chat templates drop past reasoning, some APIs refuse it), and sending it back would cost prompt
        tokens on every later call.
        """
        return ChatMessage.assistant(self.text, self.tool_calls or None)
