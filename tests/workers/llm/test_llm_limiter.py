"""The rate limiter: pure bucket and AIMD arithmetic on a fake clock, the asyncio handle, and one real-Ray run."""

from __future__ import annotations

import asyncio
import os
import time
from collections.abc import Iterator

import pytest

from tests.support.openai_server import OpenAIServer, reply, status
from workers.contract import ModelSpec, RateLimits, RetryPolicy
from workers.llm import (
    CircuitBreaker,
    Grant,
    LocalLimiterHandle,
    LocalRateLimiter,
    ModelClient,
    RateLimitState,
    Wait,
    close_litellm_clients,
    get_or_create_limiter,
)

FAST = RetryPolicy(max_attempts=4, initial_backoff_s=0.01, max_backoff_s=0.05, request_timeout_s=5, max_total_s=30)


def grant(decision: Grant | Wait) -> Grant:
    assert isinstance(decision, Grant), decision
    return decision


# -- pure state ------------------------------------------------------------------------------------------------


def test_request_bucket_spaces_requests() -> None:
    state = RateLimitState(RateLimits(requests_per_minute=60), now=0.0)  # burst 1 s: one request at once
    grant(state.acquire(0, now=0.0))
    assert state.acquire(0, now=0.0) == Wait(1.0)
    assert state.acquire(0, now=0.5) == Wait(0.5)
    grant(state.acquire(0, now=1.0))


def test_request_bucket_allows_a_burst_then_the_rate() -> None:
    state = RateLimitState(RateLimits(requests_per_minute=600, max_concurrency=100), now=0.0)
    for _ in range(10):
        grant(state.acquire(0, now=0.0))
    wait = state.acquire(0, now=0.0)
    assert isinstance(wait, Wait) and wait.seconds == pytest.approx(0.1)
    grant(state.acquire(0, now=0.1))


def test_token_bucket_charges_estimates_and_allows_one_oversized_call() -> None:
    state = RateLimitState(RateLimits(tokens_per_minute=6000), now=0.0)  # 100 tokens a second, burst 100
    grant(state.acquire(80, now=0.0))
    wait = state.acquire(50, now=0.0)
    assert isinstance(wait, Wait) and wait.seconds == pytest.approx(0.3)
    big = grant(state.acquire(500, now=1.0))  # larger than the burst: goes when the bucket is full, into debt
    assert big.estimated_tokens == 500
    wait = state.acquire(10, now=1.0)
    assert isinstance(wait, Wait) and wait.seconds == pytest.approx(4.1)


def test_release_corrects_the_charge_to_actual_usage() -> None:
    state = RateLimitState(RateLimits(tokens_per_minute=6000), now=0.0)
    lease = grant(state.acquire(100, now=0.0))
    assert isinstance(state.acquire(100, now=0.0), Wait)
    state.release(lease.lease_id, 10, "ok", now=0.0)  # used 10 of the 100 estimated: 90 come back
    assert isinstance(state.acquire(100, now=0.0), Wait)
    grant(state.acquire(90, now=0.0))


def test_concurrency_window_blocks_until_release() -> None:
    state = RateLimitState(RateLimits(max_concurrency=2), now=0.0)
    first = grant(state.acquire(0, now=0.0))
    grant(state.acquire(0, now=0.0))
    assert state.acquire(0, now=0.0) == Wait(None)
    state.release(first.lease_id, None, "error", now=1.0)
    grant(state.acquire(0, now=1.0))
    assert (state.granted, state.waits) == (3, 1)


def test_aimd_halves_once_per_round_and_grows_additively() -> None:
    state = RateLimitState(RateLimits(max_concurrency=8), now=0.0)
    old = [grant(state.acquire(0, now=0.0)) for _ in range(3)]
    state.release(old[0].lease_id, None, "rate_limited", now=1.0)
    assert state.window == 4
    state.release(old[1].lease_id, None, "rate_limited", now=1.1)  # same round: already reacted
    assert state.window == 4
    state.release(old[2].lease_id, None, "ok", now=1.2)
    assert state.window == pytest.approx(4.25)
    for now in (2.0, 3.0, 4.0, 5.0):
        state.release(grant(state.acquire(0, now=now)).lease_id, None, "rate_limited", now=now)
    assert (state.window, state.concurrency, state.decreases) == (1.0, 1, 5)
    for step in range(100):
        state.release(grant(state.acquire(0, now=10.0 + step)).lease_id, 0, "ok", now=10.0 + step)
    assert state.window == 8.0
    assert state.stats().rate_limited == 6


def test_retry_after_pauses_everyone() -> None:
    state = RateLimitState(RateLimits(), now=0.0)
    state.release(grant(state.acquire(0, now=0.0)).lease_id, None, "rate_limited", now=0.0, retry_after_s=2.0)
    assert state.acquire(0, now=0.5) == Wait(1.5)
    grant(state.acquire(0, now=2.0))


def test_expired_leases_are_reclaimed() -> None:
    state = RateLimitState(RateLimits(max_concurrency=1, lease_s=10), now=0.0)
    grant(state.acquire(0, now=0.0))
    assert state.acquire(0, now=9.0) == Wait(None)
    grant(state.acquire(0, now=10.0))
    assert state.reclaimed == 1


def test_a_lease_released_before_its_grant_is_never_granted() -> None:
    state = RateLimitState(RateLimits(), now=0.0)
    state.release("abandoned", None, "cancelled", now=0.0)
    assert state.acquire(0, now=0.0, lease_id="abandoned") == Wait(None)
    assert state.in_flight == 0


def test_a_lease_asked_for_again_is_granted_once() -> None:
    """A retried ask (its first reply lost on the way) gets the same grant, holding one slot."""
    state = RateLimitState(RateLimits(max_concurrency=2), now=0.0)
    first = grant(state.acquire(5, now=0.0, lease_id="asked-twice"))
    assert state.acquire(5, now=0.0, lease_id="asked-twice") == first
    assert (state.granted, state.in_flight) == (1, 1)
    grant(state.acquire(5, now=0.0, lease_id="another"))  # the second slot is still free
    assert state.in_flight == 2


# -- the asyncio handle ----------------------------------------------------------------------------------------


async def test_local_handle_wakes_a_waiter_on_release() -> None:
    # A waiter that polled would ask again only after max_block_s (an hour); one woken by the release at once.
    handle = LocalLimiterHandle(LocalRateLimiter(RateLimits(max_concurrency=1), max_block_s=3600))
    order: list[str] = []
    done = asyncio.Event()

    async def call(name: str, until: asyncio.Event | None) -> None:
        async with handle.slot(10) as slot:
            order.append(f"{name}+")
            if until is not None:
                await until.wait()
            order.append(f"{name}-")
            slot.report(12)

    first = asyncio.create_task(call("a", done))
    second = asyncio.create_task(call("b", None))
    for _ in range(100):  # turns of the event loop, not time: b asks (and is told to wait) within a few
        if (await handle.stats()).waits:
            break
        await asyncio.sleep(0)
    assert (order, (await handle.stats()).waits) == (["a+"], 1)
    done.set()
    async with asyncio.timeout(60):  # a hang detector only: without the wake-up b would sleep for an hour
        await asyncio.gather(first, second)
    assert order == ["a+", "a-", "b+", "b-"]
    stats = await handle.stats()
    assert (stats.in_flight, stats.granted, stats.waits) == (0, 2, 1)  # b asked twice: refused, then granted


async def test_cancelled_holders_and_waiters_free_their_slots() -> None:
    handle = LocalLimiterHandle(RateLimits(max_concurrency=1))
    entered = asyncio.Event()

    async def holder() -> None:
        async with handle.slot(0):
            entered.set()
            await asyncio.sleep(60)

    task = asyncio.create_task(holder())
    await entered.wait()
    waiter = asyncio.create_task(handle.slot(0).__aenter__())
    await asyncio.sleep(0.05)
    waiter.cancel()
    task.cancel()
    await asyncio.gather(task, waiter, return_exceptions=True)
    async with asyncio.timeout(1), handle.slot(0):
        pass
    assert (await handle.stats()).in_flight == 0


async def test_model_client_reports_throttling_to_the_limiter() -> None:
    handle = LocalLimiterHandle(RateLimits(max_concurrency=8))
    with OpenAIServer([status(429), reply("ok", 30, 5)]) as server:
        spec = ModelSpec(name="t", model="openai/limited", api_base=server.url, params={"api_key": "k"})
        completion = await ModelClient(spec, FAST, handle, CircuitBreaker("limited")).complete([])
    assert completion.attempts == 2
    stats = await handle.stats()
    assert (stats.rate_limited, stats.decreases, stats.granted, stats.in_flight) == (1, 1, 2, 0)
    assert stats.window == pytest.approx(4.25)
    await close_litellm_clients()


# -- across Ray processes --------------------------------------------------------------------------------------


@pytest.fixture(scope="module")
def ray_session() -> Iterator[object]:
    os.environ.setdefault("RAY_ENABLE_WINDOWS_OR_OSX_CLUSTER", "0")
    import ray

    ray.init(
        address="local",
        num_cpus=1,
        include_dashboard=False,
        log_to_driver=False,
        object_store_memory=100 * 2**20,
        configure_logging=False,
    )
    yield ray
    ray.shutdown()


@pytest.mark.ray
def test_two_ray_actors_share_one_limiter(ray_session: object) -> None:
    """One slot for the cluster: while one actor's call is held at the server, the other's ask reaches
    the same limiter and waits; a limiter per actor would let both calls through (no wall-clock bound)."""
    import ray

    calls = 5
    limits = RateLimits(max_concurrency=1)
    handle = get_or_create_limiter("test-shared-model", limits)  # owned by this driver
    patient = FAST.model_copy(update={"request_timeout_s": 120, "max_total_s": 240})  # a held reply is no timeout

    @ray.remote(num_cpus=0)
    class Caller:
        async def run(self, url: str, limiter: object, calls: int) -> list[int]:
            spec = ModelSpec(name="t", model="openai/shared", api_base=url, params={"api_key": "k"})
            client = ModelClient(spec, patient, limiter, CircuitBreaker("shared"))  # type: ignore[arg-type]
            return [(await client.complete([{"role": "user", "content": "hi"}])).attempts for _ in range(calls)]

    callers = [Caller.remote() for _ in range(2)]
    with OpenAIServer([status(429)]) as server:
        server.hold()
        running = [caller.run.remote(server.url, handle, calls) for caller in callers]
        deadline = time.monotonic() + 120  # a hang detector: the condition holds as soon as both actors asked
        while True:
            stats = ray.get(handle.actor().stats.remote())
            if stats.waits and server.count:
                break
            assert time.monotonic() < deadline, f"no second ask reached the shared limiter: {stats}"
            time.sleep(0.05)
        # The other actor asked this limiter and was told to wait; nothing of its reached the server.
        assert (server.count, stats.granted, stats.in_flight) == (1, 1, 1)
        server.release()
        attempts = ray.get(running, timeout=120)
        requests = server.count

    assert sorted(n for per_caller in attempts for n in per_caller) == [1] * (2 * calls - 1) + [2]
    stats = ray.get(handle.actor().stats.remote())
    assert stats.granted == requests == 2 * calls + 1  # one limiter served both actors' every attempt
    assert (stats.rate_limited, stats.decreases, stats.in_flight) == (1, 1, 0)  # one 429 moved the shared window
