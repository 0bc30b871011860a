"""One model behind LiteLLM, with our own retries, pacing, circuit breaker and errors.

LiteLLM is called with ``num_retries=0`` (its own retries would also repeat 400s and stack on
the SDK's); a tenacity loop retries transient errors with full-jitter exponential backoff,
honouring ``Retry-After``, within ``max_attempts`` and ``max_total_s``. Each HTTP attempt holds
a rate-limiter slot. Failures surface as ``ModelCallError`` with a class, and no message ever
holds the API key: it is scrubbed, and the provider's exception is not chained. With a
``ModelCache``, a request answered before is answered from it before any of that (see ``_cache``).
"""

from __future__ import annotations

import asyncio
import email.utils
import functools
import logging
import os
import random
import time
from types import ModuleType
from typing import Any

from pydantic import BaseModel
from tenacity import AsyncRetrying, RetryCallState, retry_if_exception

from workers.contract import ModelCallError, ModelErrorClass, ModelSpec, RetryPolicy
from workers.llm._breaker import CircuitBreaker, circuit_breaker
from workers.llm._cache import CACHE_FORMAT, CacheEntry, ModelCache, request_key, uncacheable
from workers.llm._limiter import RateLimiterHandle
from workers.llm._litellm import litellm_version, load_litellm, takes_seed

logger = logging.getLogger(__name__)

IMAGE_TOKENS = 1000
"""Rough token charge of one image in a prompt, for the limiter's estimate."""

DEFAULT_COMPLETION_TOKENS = 1024
"""Completion tokens assumed for the estimate when the spec sets no ``max_tokens``."""


class Completion(BaseModel):
    """A model's answer and what it cost."""

    text: str
    input_tokens: int
    output_tokens: int
    cost_usd: float
    """LiteLLM's price of the call; 0.0 for a model it has no price for."""

    latency_s: float
    """Duration of the successful HTTP attempt."""

    total_s: float
    """Duration of the whole call: limiter waits, failed attempts and backoff included."""

    attempts: int
    model: str
    """The model the provider says answered."""

    finish_reason: str | None = None
    reasoning: str | None = None
    """The reasoning the provider returned apart from the reply (LiteLLM's ``reasoning_content``), if any."""

    cached: bool = False
    """Answered from the model cache: no request was made and it cost nothing."""

    @classmethod
    def replayed(cls, entry: CacheEntry, total_s: float) -> Completion:
        """A cached reply as a completion: its usage as stored, its cost 0, no attempt made."""
        return cls(
            text=entry.text,
            input_tokens=entry.input_tokens,
            output_tokens=entry.output_tokens,
            cost_usd=0.0,
            latency_s=0.0,
            total_s=total_s,
            attempts=0,
            model=entry.answered_by,
            finish_reason=entry.finish_reason,
            reasoning=entry.reasoning,
            cached=True,
        )

    def entry(self, key: str, model: str, seed: int | None) -> CacheEntry:
        """This completion as the cache entry answering the request ``key`` (``model``: the LiteLLM string called)."""
        return CacheEntry(
            format=CACHE_FORMAT,
            key=key,
            model=model,
            seed=seed,
            text=self.text,
            input_tokens=self.input_tokens,
            output_tokens=self.output_tokens,
            cost_usd=self.cost_usd,
            answered_by=self.model,
            finish_reason=self.finish_reason,
            reasoning=self.reasoning,
            stored_at=time.time(),
        )


def model_key(spec: ModelSpec) -> str:
    """What shares a rate limit and a circuit: the model, its endpoint and its key."""
    return f"{spec.model}@{spec.api_base or 'default'}#{spec.api_key_env or '-'}"


def estimate_tokens(messages: list[dict[str, Any]], max_tokens: int | None) -> int:
    """A cheap upper-ish estimate (4 characters a token, a flat charge per image) for the limiter."""
    chars = 0
    images = 0
    for message in messages:
        content = message.get("content")
        parts = content if isinstance(content, list) else [content]
        for part in parts:
            if isinstance(part, str):
                chars += len(part)
            elif isinstance(part, dict):
                if part.get("type") == "image_url":
                    images += 1
                else:
                    chars += len(str(part.get("text", "")))
    return chars // 4 + images * IMAGE_TOKENS + (max_tokens or DEFAULT_COMPLETION_TOKENS)


_cost_warned: set[str] = set()
_uncached_warned: set[str] = set()


def _cost(litellm: ModuleType, response: Any, model: str) -> float:
    cost = (getattr(response, "_hidden_params", None) or {}).get("response_cost")
    if cost is None:
        try:
            cost = litellm.completion_cost(completion_response=response)
        except Exception:
            cost = None
    if cost is None:
        if model not in _cost_warned:
            _cost_warned.add(model)
            logger.warning("no price known for model %s: its calls are costed at 0 (register it with LiteLLM)", model)
        return 0.0
    return float(cost)


class ModelClient:
    """Calls one model; safe to share between the tasks of one event loop."""

    def __init__(
        self,
        spec: ModelSpec,
        policy: RetryPolicy | None = None,
        limiter: RateLimiterHandle | None = None,
        breaker: CircuitBreaker | None = None,
    ) -> None:
        self.spec = spec
        self.policy = policy or RetryPolicy()
        self.limiter = limiter
        self.key = model_key(spec)
        self.breaker = breaker or circuit_breaker(
            self.key, self.policy.breaker_failures, self.policy.breaker_window_s, self.policy.breaker_cooldown_s
        )

    async def complete(
        self, messages: list[dict[str, Any]], seed: int | None = None, cache: ModelCache | None = None
    ) -> Completion:
        """The model's reply to ``messages``; raises ``ModelCallError`` once retrying cannot help.

        With a ``cache``, a request answered before is answered from it (no request, no cost, no
        rate-limiter slot, whatever the circuit says) and a successful reply is stored there.
        """
        from workers.tracing import set_attributes, span  # the OpenTelemetry API: only once a model is called

        with span("model_call", model=self.spec.name, litellm_model=self.spec.model) as calling:
            completion = await self._complete_cached(messages, seed, cache)
            set_attributes(
                calling, input_tokens=completion.input_tokens, output_tokens=completion.output_tokens,
                cached=completion.cached, cost_usd=completion.cost_usd,
            )  # fmt: skip
        return completion

    async def _complete_cached(
        self, messages: list[dict[str, Any]], seed: int | None, cache: ModelCache | None
    ) -> Completion:
        started = time.monotonic()
        key = await self._cache_key(messages, seed) if cache is not None else None
        if cache is not None and key is not None:
            entry = await cache.get(key)
            if entry is not None:
                return Completion.replayed(entry, time.monotonic() - started)
        completion = await self._call(messages, seed)
        if cache is not None and key is not None:
            await cache.put(completion.entry(key, self.spec.model, seed))
        return completion

    async def _cache_key(self, messages: list[dict[str, Any]], seed: int | None) -> str | None:
        """The request's key: the model's identity, the seed, every keyword LiteLLM is given but the API
        key (the endpoint as resolved here included), every message in full, and LiteLLM's version."""
        await load_litellm()
        reason = uncacheable(self.spec, seeded=seed is not None)
        if reason is not None:  # the sweep config refuses this; an agent's own ModelSpec may not have been checked
            if self.key not in _uncached_warned:
                _uncached_warned.add(self.key)
                logger.warning("not caching: %s", reason)
            return None
        request = {
            "format": CACHE_FORMAT,
            "litellm": litellm_version(),
            "model": self.spec.identity(),
            "seed": seed,
            "kwargs": self._kwargs(None, seed),
            "messages": messages,
        }
        return await asyncio.to_thread(request_key, request)

    async def _call(self, messages: list[dict[str, Any]], seed: int | None) -> Completion:
        trial = self.breaker.before_call()
        verdict = False
        try:
            completion = await self._complete(messages, seed)
            self.breaker.record_success()
            verdict = True
            return completion
        except ModelCallError as error:
            if error.transient:
                self.breaker.record_failure()
            else:
                self.breaker.record_success()  # the provider answered; the request was at fault
            verdict = True
            raise
        finally:
            if not verdict:
                self.breaker.record_abandoned(trial)

    async def _complete(self, messages: list[dict[str, Any]], seed: int | None) -> Completion:
        litellm = await load_litellm()
        api_key = self._api_key()
        started = time.monotonic()
        deadline = started + self.policy.max_total_s
        kwargs = self._kwargs(api_key, seed)
        estimate = estimate_tokens(messages, self.spec.max_tokens)
        attempts = 0

        retrying = AsyncRetrying(
            retry=retry_if_exception(lambda exc: _classify(litellm, exc)[1]),
            wait=self._wait,
            stop=lambda state: self._stop(state, deadline),
            before_sleep=self._log_retry,
            reraise=True,
        )
        try:
            async for attempt in retrying:
                with attempt:
                    attempts += 1
                    response, latency = await self._attempt(litellm, messages, kwargs, deadline, estimate)
        except Exception as exc:
            error_class, transient = _classify(litellm, exc)
            if error_class is None:
                raise
            message = f"{self.spec.name}: {error_class} after {attempts} attempt(s): {type(exc).__name__}: {exc}"
            raise ModelCallError(
                error_class,
                _scrub(message, api_key)[:2000],
                transient=transient,
                attempts=attempts,
                status_code=getattr(exc, "status_code", None),
            ) from None  # the provider's exception text may quote the key
        usage = getattr(response, "usage", None)
        choice = response.choices[0]
        return Completion(
            text=choice.message.content or "",
            input_tokens=int(getattr(usage, "prompt_tokens", 0) or 0),
            output_tokens=int(getattr(usage, "completion_tokens", 0) or 0),
            cost_usd=_cost(litellm, response, self.spec.model),
            latency_s=latency,
            total_s=time.monotonic() - started,
            attempts=attempts,
            model=str(getattr(response, "model", None) or self.spec.model),
            finish_reason=getattr(choice, "finish_reason", None),
            reasoning=_reasoning(choice.message),
        )

    async def _attempt(
        self,
        litellm: ModuleType,
        messages: list[dict[str, Any]],
        kwargs: dict[str, Any],
        deadline: float,
        estimate: int,
    ) -> tuple[Any, float]:
        if self.limiter is None:
            return await self._request(litellm, messages, kwargs, self._timeout(deadline))
        async with self.limiter.slot(estimate) as slot:
            try:
                response, latency = await self._request(litellm, messages, kwargs, self._timeout(deadline))
            except litellm.RateLimitError as exc:
                slot.report(None, rate_limited=True, retry_after_s=_retry_after(exc))
                raise
            usage = getattr(response, "usage", None)
            slot.report(getattr(usage, "total_tokens", None))
            return response, latency

    async def _request(
        self, litellm: ModuleType, messages: list[dict[str, Any]], kwargs: dict[str, Any], request_timeout_s: float
    ) -> tuple[Any, float]:
        start = time.monotonic()
        response = await litellm.acompletion(messages=messages, timeout=request_timeout_s, num_retries=0, **kwargs)
        return response, time.monotonic() - start

    def _timeout(self, deadline: float) -> float:
        """The request timeout, cut to what is left of ``max_total_s`` (after any limiter wait)."""
        return max(0.001, min(self.policy.request_timeout_s, deadline - time.monotonic()))

    def _kwargs(self, api_key: str | None, seed: int | None) -> dict[str, Any]:
        spec = self.spec
        kwargs: dict[str, Any] = {"model": spec.model, **spec.params}
        optional = {"api_base": self._api_base(), "api_key": api_key, "temperature": spec.temperature}
        kwargs.update({name: value for name, value in optional.items() if value is not None})
        if spec.max_tokens is not None:
            kwargs["max_tokens"] = spec.max_tokens
        if seed is not None:
            if takes_seed(spec.model):
                kwargs["seed"] = seed
            else:
                logger.debug("%s does not take a seed; calling without one", spec.model)
        return kwargs

    def _api_base(self) -> str | None:
        name = self.spec.api_base_env
        if name is None:
            return self.spec.api_base
        value = os.environ.get(name)
        if not value:
            message = f"{self.spec.name}: environment variable {name} (the model's base URL) is not set"
            raise ModelCallError("model_bad_request", message, transient=False, attempts=0)
        return value

    def _api_key(self) -> str | None:
        name = self.spec.api_key_env
        if name is None:
            return None
        value = os.environ.get(name)
        if not value:
            raise ModelCallError(
                "model_auth", f"{self.spec.name}: environment variable {name} is not set", transient=False, attempts=0
            )
        return value

    def _wait(self, state: RetryCallState) -> float:
        exc = state.outcome.exception() if state.outcome is not None else None
        retry_after = _retry_after(exc) if exc is not None else None
        if retry_after is not None:
            return min(retry_after, self.policy.max_retry_after_s)
        ceiling = min(self.policy.max_backoff_s, self.policy.initial_backoff_s * 2 ** (state.attempt_number - 1))
        return random.uniform(0, ceiling)

    def _stop(self, state: RetryCallState, deadline: float) -> bool:
        if state.attempt_number >= self.policy.max_attempts:
            return True
        return time.monotonic() + (state.upcoming_sleep or 0.0) >= deadline

    def _log_retry(self, state: RetryCallState) -> None:
        exc = state.outcome.exception() if state.outcome is not None else None
        logger.info(
            "%s: attempt %d/%d failed (%s, HTTP %s); retrying in %.2f s",
            self.spec.name,
            state.attempt_number,
            self.policy.max_attempts,
            type(exc).__name__,
            getattr(exc, "status_code", None),
            state.upcoming_sleep,
        )


def _classify(litellm: ModuleType, exc: BaseException) -> tuple[ModelErrorClass | None, bool]:
    """Our class for a LiteLLM error and whether retrying may help; (None, False) for anything else.

    Permanent classes are checked first: the context-window and content-policy errors subclass
    ``BadRequestError``. A refused or dropped connection arrives as ``InternalServerError``, so
    the cause chain decides between ``connection`` and ``provider_error``.
    """
    if isinstance(exc, litellm.ContextWindowExceededError):
        return "model_context_window", False
    if isinstance(exc, litellm.ContentPolicyViolationError):
        return "model_content_policy", False
    if isinstance(exc, (litellm.AuthenticationError, litellm.PermissionDeniedError)):
        return "model_auth", False
    if isinstance(exc, litellm.NotFoundError):
        return "model_not_found", False
    if isinstance(exc, (litellm.BadRequestError, litellm.UnprocessableEntityError)):
        return "model_bad_request", False
    if isinstance(exc, litellm.RateLimitError):
        return "model_rate_limited", True
    if isinstance(exc, litellm.Timeout):
        return "model_timeout", True
    if isinstance(exc, litellm.APIConnectionError):
        return "model_connection", True
    openai_errors = _openai_error_types()
    for cause in _chain(exc):
        if type(cause) is openai_errors[2]:  # raised by the SDK before any request: no credentials
            return "model_auth", False
        if isinstance(cause, openai_errors[1]):
            return "model_timeout", True
        if isinstance(cause, openai_errors[0]):
            return "model_connection", True
    if isinstance(exc, (litellm.InternalServerError, litellm.ServiceUnavailableError, litellm.BadGatewayError)):
        return "model_provider_error", True
    status = getattr(exc, "status_code", None)
    if isinstance(status, int) and isinstance(exc, (litellm.APIError, litellm.APIResponseValidationError)):
        return _STATUS_CLASSES.get(status) or (
            ("model_provider_error", True) if status >= 500 else ("model_bad_request", False)
        )
    if isinstance(exc, (litellm.APIError, litellm.APIResponseValidationError)):
        return "model_provider_error", True
    return None, False


_STATUS_CLASSES: dict[int, tuple[ModelErrorClass, bool]] = {
    401: ("model_auth", False),
    403: ("model_auth", False),
    404: ("model_not_found", False),
    408: ("model_timeout", True),
    413: ("model_context_window", False),
    429: ("model_rate_limited", True),
}
"""Classes of the status codes LiteLLM leaves as a plain ``APIError`` (e.g. 403 from an OpenAI-compatible server)."""


@functools.cache
def _openai_error_types() -> tuple[type[BaseException], type[BaseException], type[BaseException]]:
    import openai

    return openai.APIConnectionError, openai.APITimeoutError, openai.OpenAIError


def _chain(exc: BaseException) -> list[BaseException]:
    seen: list[BaseException] = []
    current: BaseException | None = exc.__cause__ or exc.__context__
    while current is not None and len(seen) < 10:
        seen.append(current)
        current = current.__cause__ or current.__context__
    return seen


def _retry_after(exc: BaseException) -> float | None:
    """Seconds the provider asked us to wait (``retry-after-ms``, ``retry-after`` in seconds or as a date)."""
    for candidate in (exc, *_chain(exc)):
        for headers in (
            getattr(candidate, "litellm_response_headers", None),
            getattr(getattr(candidate, "response", None), "headers", None),
        ):
            if not headers:
                continue
            value = _parse_retry_after(headers.get("retry-after-ms"), headers.get("retry-after"))
            if value is not None:
                return value
    return None


def _parse_retry_after(milliseconds: str | None, value: str | None) -> float | None:
    if milliseconds:
        try:
            return max(0.0, float(milliseconds) / 1000)
        except ValueError:
            pass
    if not value:
        return None
    try:
        return max(0.0, float(value))
    except ValueError:
        pass
    try:
        when = email.utils.parsedate_to_datetime(value)
    except (TypeError, ValueError):
        return None
    return max(0.0, when.timestamp() - time.time())


def _scrub(text: str, secret: str | None) -> str:
    if secret and len(secret) >= 4:
        text = text.replace(secret, "[redacted]")
    return text


def _reasoning(message: Any) -> str | None:
    """The reasoning LiteLLM found in the provider's reply (its ``reasoning_content``), when it is text."""
    reasoning = getattr(message, "reasoning_content", None)
    return reasoning if isinstance(reasoning, str) and reasoning else None
