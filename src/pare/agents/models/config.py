"""How one role reaches its model: backend, endpoint, sampling settings, retries, prices."""

from __future__ import annotations

from typing import Any, Literal
from urllib.parse import urlsplit, urlunsplit

from pydantic import (
    BaseModel,
    ConfigDict,
    Field,
    JsonValue,
    ValidationError,
    field_validator,
    model_validator,
)

from pare.agents.models.secrets import redact_secrets
from pare.errors import UserInputError

Backend = Literal["openai", "litellm"]
"""``openai``: the OpenAI SDK, for OpenAI and every OpenAI-compatible server (vLLM, Ollama, OpenRouter).
``litellm``: litellm, for providers reached natively (Anthropic, Gemini, Bedrock, ...); an optional extra."""

ROLES: tuple[str, ...] = ("user", "observe", "execute", "judge", "generator")
"""The roles PARE's actors play; a role is only a name used in messages, the ledger and provenance."""

DEFAULT_API_KEY_ENV: dict[str, str | None] = {"openai": "OPENAI_API_KEY", "litellm": None}
"""The variable read for the key when a configuration does not name one. litellm with ``None`` finds the
provider's usual variable itself (``ANTHROPIC_API_KEY``, ``GEMINI_API_KEY``, ...)."""

DEFAULT_MAX_ANSWER_CHARS = 65_536
"""The longest answer kept by default: far above any action or scenario section (a few KB), far below what
a runaway model writes (an answer of 1 MB made one episode write 1.3 GB: every later request repeats it)."""

RESERVED_REQUEST_KEYS = frozenset(
    {
        "model",
        "messages",
        "tools",
        "temperature",
        "max_tokens",
        "seed",
        "timeout",
        "api_key",
        "api_base",
        "base_url",
        "stream",
        "n",
        "max_retries",
        "num_retries",
    }
)
"""Request parameters a configuration sets through its own fields, never through ``extra``."""


MAX_BUDGET_PER_MINUTE = 10**12
"""The largest requests_per_minute or tokens_per_minute a configuration may set."""


class Prices(BaseModel):
    """Prices of one model in US dollars per million tokens."""

    model_config = ConfigDict(extra="forbid", frozen=True, allow_inf_nan=False)

    input: float = Field(ge=0.0, description="USD per million prompt tokens that were not served from cache.")
    output: float = Field(ge=0.0, description="USD per million completion tokens.")
    cached_input: float | None = Field(
        default=None,
        ge=0.0,
        description="USD per million prompt tokens served from the provider's prompt cache "
        "(defaults to the input price).",
    )

    def cost(self, prompt_tokens: int, completion_tokens: int, cached_tokens: int = 0) -> float:
        """Return the price of one call; ``cached_tokens`` are part of ``prompt_tokens``."""
        cached = min(max(cached_tokens, 0), prompt_tokens)
        cached_price = self.input if self.cached_input is None else self.cached_input
        return (
            (prompt_tokens - cached) * self.input + cached * cached_price + completion_tokens * self.output
        ) / 1e6


class ModelConfig(BaseModel):
    """Everything needed to call one role's model. Secrets never live here, only their variable's name."""

    model_config = ConfigDict(extra="forbid", frozen=True, allow_inf_nan=False)

    model: str = Field(
        min_length=1,
        description="The model's name as the endpoint knows it ('gpt-4o-mini'; for litellm with the "
        "provider prefix: 'anthropic/claude-3-5-sonnet-latest', 'openai/<name>' for an OpenAI-compatible "
        "server).",
    )
    backend: Backend = Field(default="openai", description="Which client library makes the call.")
    api_base: str | None = Field(
        default=None, description="The endpoint's base URL, e.g. 'http://localhost:8000/v1' for vLLM."
    )
    api_key_env: str | None = Field(
        default=None,
        description="Name of the environment variable holding the API key (default 'OPENAI_API_KEY' for "
        "the openai backend). None: no key (a local server; a dummy key is sent) or, with litellm, the "
        "provider's usual variable.",
    )
    temperature: float | None = Field(
        default=None,
        ge=0.0,
        le=10.0,
        description="Sampling temperature; None: not sent, the provider's default applies (reasoning "
        "models accept no other).",
    )
    max_tokens: int | None = Field(
        default=None, gt=0, le=10_000_000, description="Most tokens the model may generate."
    )
    seed: int | None = Field(default=None, description="Sampling seed, for providers that honour one.")
    extra: dict[str, JsonValue] = Field(
        default_factory=dict,
        description="Further request parameters (top_p, stop, reasoning_effort, ...), sent where the "
        "model accepts them.",
    )
    timeout_s: float = Field(default=60.0, gt=0.0, le=86_400.0, description="Seconds one request may take.")
    max_retries: int = Field(
        default=5, ge=0, le=100, description="Retries of a transient failure before giving up."
    )
    retry_initial_s: float = Field(default=1.0, ge=0.0, le=3_600.0, description="First wait before a retry.")
    retry_max_s: float = Field(
        default=30.0, ge=0.0, le=3_600.0, description="Longest wait between two attempts."
    )
    max_concurrency: int = Field(
        default=16,
        ge=1,
        le=10_000,
        description="Most requests in flight at once to this endpoint (from one process); rate-limit "
        "answers (429) lower the limit for a while.",
    )
    requests_per_minute: int | None = Field(
        default=None,
        description="Most requests started in any minute at this endpoint (from one process), paced "
        "evenly; None: no budget.",
    )
    tokens_per_minute: int | None = Field(
        default=None,
        description="Tokens (prompt and completion) per minute at this endpoint (from one process), paced "
        "evenly from an estimate before each call and the usage reported after it; None: no budget.",
    )
    prices: Prices | None = Field(
        default=None, description="Prices to use instead of litellm's price table (USD per million tokens)."
    )
    native_tools: bool = Field(
        default=False, description="Send tool schemas through the provider's function-calling API."
    )
    max_answer_chars: int = Field(
        default=DEFAULT_MAX_ANSWER_CHARS,
        ge=1,
        le=100_000_000,
        description="Longest answer kept, in characters (text plus tool-call arguments; reasoning apart): "
        "a longer one is cut to this length in the records and the cache, and is a format error for the "
        "model.",
    )

    @model_validator(mode="before")
    @classmethod
    def _default_api_key_env(cls, data: Any) -> Any:
        if isinstance(data, dict) and "api_key_env" not in data:
            backend = data.get("backend", "openai")
            if isinstance(backend, str) and backend in DEFAULT_API_KEY_ENV:
                return {**data, "api_key_env": DEFAULT_API_KEY_ENV[backend]}
        return data

    @field_validator("api_key_env")
    @classmethod
    def _variable_name(cls, value: str | None) -> str | None:
        if value is not None and (not value or any(c.isspace() for c in value) or value.startswith("sk-")):
            raise ValueError(
                "must be the NAME of an environment variable holding the key (e.g. 'OPENAI_API_KEY'), "
                "never the key itself"
            )
        return value

    @field_validator("api_base")
    @classmethod
    def _http_url(cls, value: str | None) -> str | None:
        # A value that is not an http(s) URL would be retried as an outage, then counted as missing
        # coverage; it is a mistake in the configuration. The value is not repeated: it may hold a key.
        if value is None:
            return value
        wanted = "must be an http:// or https:// URL with a host, e.g. 'http://localhost:8000/v1'"
        try:
            parts = urlsplit(value)
            _ = parts.port  # a port that is not a number raises here
        except ValueError as error:
            raise ValueError(f"{wanted} (this one cannot be read: {error})") from None
        if parts.scheme.lower() not in ("http", "https") or "://" not in value:
            given = f" (this one starts with '{parts.scheme}://')" if "://" in value and parts.scheme else ""
            raise ValueError(wanted + given)
        if not parts.hostname:
            raise ValueError(f"{wanted} (this one names no host)")
        return value

    @field_validator("extra")
    @classmethod
    def _no_reserved_keys(cls, value: dict[str, JsonValue]) -> dict[str, JsonValue]:
        clash = sorted(RESERVED_REQUEST_KEYS & value.keys())
        if clash:
            raise ValueError(
                f"{', '.join(clash)} cannot be set through 'extra': use the configuration's own fields"
            )
        return value

    @field_validator("requests_per_minute", "tokens_per_minute", mode="before")
    @classmethod
    def _budget_is_a_number(cls, value: Any) -> Any:
        if isinstance(value, bool):  # YAML's yes/no would otherwise count as 1 and 0
            raise ValueError(_budget_problem(value))
        return value

    @field_validator("requests_per_minute", "tokens_per_minute")
    @classmethod
    def _budget_in_range(cls, value: int | None) -> int | None:
        if value is not None and not 1 <= value <= MAX_BUDGET_PER_MINUTE:
            raise ValueError(_budget_problem(value))
        return value

    @model_validator(mode="after")
    def _retry_waits(self) -> ModelConfig:
        if self.retry_max_s < self.retry_initial_s:
            raise ValueError("retry_max_s must be at least retry_initial_s")
        return self

    @classmethod
    def parse(cls, data: Any, *, where: str = "model configuration") -> ModelConfig:
        """Validate ``data``, raising :class:`UserInputError` that lists every problem with its field."""
        try:
            return cls.model_validate(data)
        except ValidationError as error:
            problems = "; ".join(
                f"{'.'.join(str(p) for p in e['loc']) or '(top level)'}: {e['msg']}" for e in error.errors()
            )
            raise UserInputError(f"{where}: {problems}") from None

    def endpoint(self) -> str:
        """Name the endpoint for messages: the base URL without credentials, or the provider's default."""
        if self.api_base:
            return redact_url(self.api_base)
        if self.backend == "openai":
            return "https://api.openai.com/v1 (default)"
        provider = self.model.split("/", 1)[0] if "/" in self.model else "provider"
        return f"{provider} default endpoint (litellm)"

    def request_params(self) -> dict[str, JsonValue]:
        """Return the request parameters this configuration sets, and only those: nothing is sent that
        the configuration leaves unset, so the provider's defaults apply. What each request actually
        carries can differ by model (see :mod:`pare.agents.models.capabilities`).
        """
        params: dict[str, JsonValue] = {}
        if self.temperature is not None:
            params["temperature"] = self.temperature
        if self.max_tokens is not None:
            params["max_tokens"] = self.max_tokens
        if self.seed is not None:
            params["seed"] = self.seed
        params.update(self.extra)
        return params

    def public_dict(self) -> dict[str, Any]:
        """Return the settings as JSON for provenance: no secret (secret-looking ``extra`` entries and every
        header value masked), credentials stripped from the URL.
        """
        data: dict[str, Any] = redact_secrets(self.model_dump(mode="json"))
        if self.api_base:
            data["api_base"] = redact_url(self.api_base)
        return data


def _budget_problem(value: object) -> str:
    return (
        f"must be a whole number from 1 to {MAX_BUDGET_PER_MINUTE:,} (leave it unset, or null, for no "
        f"budget), not {value!r}"
    )


def redact_url(url: str) -> str:
    """Drop a user name, password and query string (which may carry a key) from ``url``."""
    parts = urlsplit(url)
    if parts.username is None and parts.password is None and not parts.query:
        return url
    host = parts.hostname or ""
    if parts.port is not None:
        host = f"{host}:{parts.port}"
    if parts.username is not None or parts.password is not None:
        host = f"***@{host}"
    return urlunsplit((parts.scheme, host, parts.path, "***" if parts.query else "", parts.fragment))
