"""The model-calling foundation of the ``llm`` agent: reply parsing, the model client, cluster-wide pacing
and the opt-in model-call cache.

Importing this package does not import LiteLLM (2-3 s and, without the offline cost map, the
network) nor Ray; both load on first use.
"""

from workers.llm._breaker import BreakerState, CircuitBreaker, circuit_breaker
from workers.llm._cache import CacheEntry, ModelCache, request_key, uncacheable
from workers.llm._client import Completion, ModelClient, estimate_tokens, model_key
from workers.llm._limiter import (
    LIMITER_NAMESPACE,
    Grant,
    LimiterStats,
    LocalLimiterHandle,
    LocalRateLimiter,
    Outcome,
    RateLimiterActor,
    RateLimiterHandle,
    RateLimitState,
    RayLimiterHandle,
    Slot,
    Wait,
    get_or_create_limiter,
)
from workers.llm._litellm import close_litellm_clients, litellm_version, load_litellm, takes_seed
from workers.llm._parsing import EXPECTED_FORMAT, ParsedReply, ParseFailure, ReplyParseError, parse_reply
from workers.llm._probe import PROBE_MESSAGES, check_models, probe_model, setting_problem
from workers.llm._repair import repair_json

__all__ = [
    "EXPECTED_FORMAT",
    "LIMITER_NAMESPACE",
    "PROBE_MESSAGES",
    "BreakerState",
    "CacheEntry",
    "CircuitBreaker",
    "Completion",
    "Grant",
    "LimiterStats",
    "LocalLimiterHandle",
    "LocalRateLimiter",
    "ModelCache",
    "ModelClient",
    "Outcome",
    "ParseFailure",
    "ParsedReply",
    "RateLimitState",
    "RateLimiterActor",
    "RateLimiterHandle",
    "RayLimiterHandle",
    "ReplyParseError",
    "Slot",
    "Wait",
    "check_models",
    "circuit_breaker",
    "close_litellm_clients",
    "estimate_tokens",
    "get_or_create_limiter",
    "litellm_version",
    "load_litellm",
    "model_key",
    "parse_reply",
    "probe_model",
    "repair_json",
    "request_key",
    "setting_problem",
    "takes_seed",
    "uncacheable",
]
