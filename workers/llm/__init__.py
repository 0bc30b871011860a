"""The model-calling foundation of the ``llm`` agent: reply parsing, the model client and cluster-wide pacing.

Importing this package does not import LiteLLM (2-3 s and, without the offline cost map, the
network) nor Ray; both load on first use.
"""

from workers.llm._breaker import BreakerState, CircuitBreaker, circuit_breaker
from workers.llm._client import (
    Completion,
    ModelClient,
    RetryPolicy,
    close_litellm_clients,
    estimate_tokens,
    load_litellm,
    model_key,
)
from workers.llm._errors import ModelCallError, ModelErrorClass, ParseFailure, ReplyParseError
from workers.llm._limiter import (
    LIMITER_NAMESPACE,
    Grant,
    LimiterStats,
    LocalLimiterHandle,
    LocalRateLimiter,
    Outcome,
    RateLimiterActor,
    RateLimiterHandle,
    RateLimits,
    RateLimitState,
    RayLimiterHandle,
    Slot,
    Wait,
    get_or_create_limiter,
)
from workers.llm._parsing import EXPECTED_FORMAT, ParsedReply, parse_reply
from workers.llm._repair import repair_json
from workers.llm._settings import CoordinateSystem, LLMSettings

__all__ = [
    "EXPECTED_FORMAT",
    "LIMITER_NAMESPACE",
    "BreakerState",
    "CircuitBreaker",
    "Completion",
    "CoordinateSystem",
    "Grant",
    "LLMSettings",
    "LimiterStats",
    "LocalLimiterHandle",
    "LocalRateLimiter",
    "ModelCallError",
    "ModelClient",
    "ModelErrorClass",
    "Outcome",
    "ParseFailure",
    "ParsedReply",
    "RateLimitState",
    "RateLimiterActor",
    "RateLimiterHandle",
    "RateLimits",
    "RayLimiterHandle",
    "ReplyParseError",
    "RetryPolicy",
    "Slot",
    "Wait",
    "circuit_breaker",
    "close_litellm_clients",
    "estimate_tokens",
    "get_or_create_limiter",
    "load_litellm",
    "model_key",
    "parse_reply",
    "repair_json",
]
