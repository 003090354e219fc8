"""The model-client layer: the one way every role (user, observe, execute, judge, generator) calls a model.

Two backends (the OpenAI SDK for OpenAI and OpenAI-compatible servers; litellm, an optional extra, for
other providers), retries of transient provider errors, a record/replay cache, and tokens and cost per
call and per role, and one limiter per endpoint (adaptive concurrency, the provider's pauses after a
429, optional request and token budgets). Neither SDK is imported until the first call.

```python
from pare.agents.models import ChatMessage, ModelClient, ModelConfig

client = ModelClient(ModelConfig(model="gpt-4o-mini"), role="user")
answer = client.complete_sync([ChatMessage.user("Say hi")])
print(answer.text, answer.usage, answer.cost_usd)
```
"""

from pare.agents.models.backends import (
    BackendResponse,
    LiteLLMBackend,
    ModelBackend,
    OpenAIBackend,
    classify_error,
    litellm_available,
    make_backend,
)
from pare.agents.models.cache import CACHE_MODES, CacheMode, ModelCallCache, cache_key, request_record
from pare.agents.models.client import ModelClient, endpoint_key, endpoint_limiter
from pare.agents.models.config import ROLES, Backend, ModelConfig, Prices
from pare.agents.models.ledger import RoleUsage, UsageLedger
from pare.agents.models.limiter import EndpointLimiter, LimiterState
from pare.agents.models.pricing import call_cost, price_source
from pare.agents.models.types import ChatMessage, Completion, ToolCall, Usage

__all__ = [
    "CACHE_MODES",
    "ROLES",
    "Backend",
    "BackendResponse",
    "CacheMode",
    "ChatMessage",
    "Completion",
    "EndpointLimiter",
    "LimiterState",
    "LiteLLMBackend",
    "ModelBackend",
    "ModelCallCache",
    "ModelClient",
    "ModelConfig",
    "OpenAIBackend",
    "Prices",
    "RoleUsage",
    "ToolCall",
    "Usage",
    "UsageLedger",
    "cache_key",
    "call_cost",
    "classify_error",
    "endpoint_key",
    "endpoint_limiter",
    "litellm_available",
    "make_backend",
    "price_source",
    "request_record",
]
