"""The preflight of the models a sweep calls, run where its workers run (their environment holds the keys).

Each model's settings are checked first: the variable ``api_key_env`` names is set, and its base URL
(``api_base``, or the variable ``api_base_env`` names) is set and well formed. Probing then makes one
smallest call per model through ``ModelClient``, as an episode calls it (same keyword arguments, same
retries of 429s, 5xx and timeouts), with ``max_tokens`` 1; a model that refuses so short an answer (a 400)
is asked once more with its own settings. No cache, no rate limiter (one call), and a circuit breaker of
its own, so a probe never trips the one episodes share.
"""

from __future__ import annotations

import asyncio
import os
import sys
from collections.abc import Mapping, Sequence

from pydantic import HttpUrl, TypeAdapter, ValidationError

from workers.contract import ModelCallError, ModelCheck, ModelErrorClass, ModelSpec, RetryPolicy
from workers.llm._breaker import CircuitBreaker
from workers.llm._client import Completion, ModelClient, model_key
from workers.llm._litellm import close_litellm_clients

PROBE_MESSAGES = [{"role": "user", "content": "Reply with the single word OK."}]
PROBE_MAX_TOKENS = 1
CAUSE_CHARS = 300
"""A cause is one line of at most this many characters."""

_URL = TypeAdapter(HttpUrl)


def setting_problem(spec: ModelSpec, environ: Mapping[str, str]) -> tuple[ModelErrorClass, str] | None:
    """Why ``spec`` cannot be called in ``environ`` without calling it (None: nothing found); never quotes a value."""
    if spec.api_key_env is not None and not environ.get(spec.api_key_env):
        return "model_auth", f"environment variable {spec.api_key_env} (its API key) is not set"
    base, where = spec.api_base, "api_base"
    if spec.api_base_env is not None:
        base, where = environ.get(spec.api_base_env), f"environment variable {spec.api_base_env}"
        if not base:
            return "model_bad_request", f"{where} (its base URL) is not set"
    if base is not None:
        try:
            _URL.validate_python(base)
        except ValidationError:
            return "model_bad_request", f"{where} holds no well-formed http(s) URL"
    return None


def check_models(models: Sequence[ModelSpec], policy: RetryPolicy, probe: bool) -> list[ModelCheck]:
    """Each model checked (and with ``probe`` called once), in order; LiteLLM is imported only to probe."""
    if not probe:
        return [_settings_check(spec) for spec in models]
    return asyncio.run(_probe_all(models, policy))


def _settings_check(spec: ModelSpec) -> ModelCheck:
    problem = setting_problem(spec, os.environ)
    if problem is None:
        return ModelCheck(name=spec.name, model=spec.model)
    return ModelCheck(name=spec.name, model=spec.model, error_class=problem[0], cause=problem[1])


async def _probe_all(models: Sequence[ModelSpec], policy: RetryPolicy) -> list[ModelCheck]:
    try:
        return list(await asyncio.gather(*(probe_model(spec, policy) for spec in models)))
    finally:
        await _forget_loop_clients()


async def probe_model(spec: ModelSpec, policy: RetryPolicy) -> ModelCheck:
    """One smallest call to ``spec`` (two when the model refuses a one-token answer): what it cost, or why it failed."""
    checked = _settings_check(spec)
    if checked.broken:
        return checked
    attempts = 0
    short = spec.model_copy(update={"max_tokens": PROBE_MAX_TOKENS})
    for asked in (short, spec):
        try:
            completion = await _call(asked, policy)
        except ModelCallError as error:
            attempts += error.attempts
            if error.error_class == "model_bad_request" and asked is short:
                continue  # e.g. a thinking budget above max_tokens: ask as the episodes will
            return _failed(spec, error.error_class, str(error), attempts)
        except Exception as error:
            return _failed(spec, "model_bad_request", f"{type(error).__name__}: {error}", attempts)
        return _answered(spec, completion, attempts)
    raise AssertionError("unreachable: the second call either answers or fails")


async def _call(spec: ModelSpec, policy: RetryPolicy) -> Completion:
    breaker = CircuitBreaker(f"preflight:{model_key(spec)}", failures=policy.max_attempts + 1)
    return await ModelClient(spec, policy, limiter=None, breaker=breaker).complete(PROBE_MESSAGES)


def _answered(spec: ModelSpec, completion: Completion, earlier_attempts: int) -> ModelCheck:
    return ModelCheck(
        name=spec.name,
        model=spec.model,
        probed=True,
        attempts=earlier_attempts + completion.attempts,
        input_tokens=completion.input_tokens,
        output_tokens=completion.output_tokens,
        cost_usd=completion.cost_usd,
        latency_s=completion.latency_s,
    )


def _failed(spec: ModelSpec, error_class: ModelErrorClass, message: str, attempts: int) -> ModelCheck:
    """The failure as one line, without the model's name in front (the terminal puts it there) nor its key."""
    key = os.environ.get(spec.api_key_env) if spec.api_key_env else None
    if key and len(key) >= 4:
        message = message.replace(key, "[redacted]")
    message = message.removeprefix(f"{spec.name}: ").removeprefix(f"{error_class} ")  # the line names both
    line = " ".join(message.split())
    if len(line) > CAUSE_CHARS:
        line = line[: CAUSE_CHARS - 3] + "..."
    return ModelCheck(
        name=spec.name, model=spec.model, probed=True, error_class=error_class, cause=line, attempts=attempts
    )


async def _forget_loop_clients() -> None:
    """Close LiteLLM's HTTP clients and drop this loop's from its cache: the loop ends here, and a later loop
    given the same ``id`` must not be handed a closed client."""
    await close_litellm_clients()
    litellm = sys.modules.get("litellm")
    cache = getattr(litellm, "in_memory_llm_clients_cache", None)
    entries = getattr(cache, "cache_dict", None)
    if cache is None or not isinstance(entries, dict):
        return
    suffix = f"-{id(asyncio.get_running_loop())}"
    for key in [key for key in entries if isinstance(key, str) and key.endswith(suffix)]:
        cache.delete_cache(key)
