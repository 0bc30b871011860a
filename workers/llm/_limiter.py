"""Cluster-wide pacing of calls to one model: request and token budgets plus an AIMD concurrency window.

Three layers, so the logic is testable without a cluster or a clock:

- ``RateLimitState`` is pure: token buckets for requests/min and tokens/min, and a concurrency
  window that halves on a 429 (at most once per round of in-flight calls) and grows by
  ``1/window`` per success up to ``max_concurrency``. Time is passed in.
- ``LocalRateLimiter`` wraps it with asyncio: ``acquire`` blocks briefly until a slot frees.
  ``RateLimiterActor`` is the same class run as a Ray actor, one named actor per model key.
- A ``RateLimiterHandle`` is what ``ModelClient`` holds: ``async with handle.slot(n) as slot``.

Leases carry caller-chosen ids and expire after ``lease_s``, so a caller that dies or is
cancelled while holding (or still asking for) a slot cannot shrink the window for good.
"""

from __future__ import annotations

import asyncio
import contextlib
import functools
import logging
import math
import time
import uuid
from abc import ABC, abstractmethod
from collections import OrderedDict
from collections.abc import AsyncIterator
from dataclasses import dataclass, field
from typing import Any, Literal

from pydantic import BaseModel

from workers.contract import RateLimits

logger = logging.getLogger(__name__)

Outcome = Literal["ok", "rate_limited", "error", "cancelled"]
"""How a call that held a slot ended."""

LIMITER_NAMESPACE = "scratchworld"
"""Ray namespace of the named limiter actors (the driver's and the workers' must agree)."""

_TOMBSTONES = 4096


@dataclass(frozen=True)
class Grant:
    """Permission to make one call; release it with its ``lease_id``."""

    lease_id: str
    estimated_tokens: int


@dataclass(frozen=True)
class Wait:
    """No slot now; ask again after ``seconds`` (None: when a slot is released)."""

    seconds: float | None


class LimiterStats(BaseModel):
    """A snapshot of a limiter, for tests and progress reports."""

    window: float
    concurrency: int
    in_flight: int
    granted: int
    waits: int
    """Asks answered with a wait: a budget or the window was full (a caller elsewhere may hold the slot)."""
    rate_limited: int
    decreases: int
    reclaimed: int


@dataclass
class _Bucket:
    """A token bucket that may go into debt, so a call larger than the burst still gets through."""

    per_minute: int
    burst_s: float
    level: float
    updated: float

    @property
    def capacity(self) -> float:
        return max(1.0, self.per_minute * self.burst_s / 60)

    @property
    def rate(self) -> float:
        return self.per_minute / 60

    def refill(self, now: float) -> None:
        self.level = min(self.capacity, self.level + max(0.0, now - self.updated) * self.rate)
        self.updated = now

    def wait_for(self, cost: float) -> float:
        """Seconds until ``cost`` may be taken (0 when it may be now)."""
        needed = min(cost, self.capacity) - self.level
        return 0.0 if needed <= 1e-9 else needed / self.rate

    def take(self, cost: float) -> None:
        self.level = min(self.capacity, self.level - cost)


@dataclass
class _Lease:
    estimated_tokens: int
    granted_at: float
    expires_at: float


@dataclass
class RateLimitState:
    """The limiter's bookkeeping; every method takes ``now`` (seconds on one monotonic clock)."""

    limits: RateLimits
    now: float = 0.0
    window: float = field(init=False)
    paused_until: float = field(init=False, default=-math.inf)
    last_decrease: float = field(init=False, default=-math.inf)
    granted: int = field(init=False, default=0)
    waits: int = field(init=False, default=0)
    rate_limited: int = field(init=False, default=0)
    decreases: int = field(init=False, default=0)
    reclaimed: int = field(init=False, default=0)
    _leases: dict[str, _Lease] = field(init=False, default_factory=dict)
    _tombstones: OrderedDict[str, None] = field(init=False, default_factory=OrderedDict)
    _requests: _Bucket | None = field(init=False, default=None)
    _tokens: _Bucket | None = field(init=False, default=None)

    def __post_init__(self) -> None:
        self.window = float(self.limits.max_concurrency)
        burst = self.limits.burst_s
        if self.limits.requests_per_minute:
            bucket = _Bucket(self.limits.requests_per_minute, burst, 0.0, self.now)
            bucket.level = bucket.capacity
            self._requests = bucket
        if self.limits.tokens_per_minute:
            bucket = _Bucket(self.limits.tokens_per_minute, burst, 0.0, self.now)
            bucket.level = bucket.capacity
            self._tokens = bucket

    @property
    def concurrency(self) -> int:
        """Calls allowed in flight now: the window rounded down, at least 1."""
        return max(1, int(self.window + 1e-9))

    @property
    def in_flight(self) -> int:
        return len(self._leases)

    def acquire(self, estimated_tokens: int, now: float, lease_id: str | None = None) -> Grant | Wait:
        """Grant a slot if every budget allows it now, else say how long to wait; consumes nothing on a wait."""
        self._reclaim(now)
        lease_id = lease_id or uuid.uuid4().hex
        if lease_id in self._tombstones:
            return Wait(None)  # released (cancelled) before it was granted
        if (held := self._leases.get(lease_id)) is not None:  # asked again (a retried call): granted once
            return Grant(lease_id, held.estimated_tokens)
        if now < self.paused_until:
            self.waits += 1
            return Wait(self.paused_until - now)
        if len(self._leases) >= self.concurrency:
            self.waits += 1
            return Wait(None)
        waits = []
        for bucket, cost in ((self._requests, 1), (self._tokens, estimated_tokens)):
            if bucket is not None:
                bucket.refill(now)
                waits.append(bucket.wait_for(cost))
        if any(waits):
            self.waits += 1
            return Wait(max(waits))
        if self._requests is not None:
            self._requests.take(1)
        if self._tokens is not None:
            self._tokens.take(estimated_tokens)
        self._leases[lease_id] = _Lease(estimated_tokens, now, now + self.limits.lease_s)
        self.granted += 1
        return Grant(lease_id, estimated_tokens)

    def release(
        self,
        lease_id: str,
        actual_tokens: int | None,
        outcome: Outcome,
        now: float,
        retry_after_s: float | None = None,
    ) -> None:
        """End a lease: correct the token charge and move the window (AIMD) by the outcome."""
        lease = self._leases.pop(lease_id, None)
        if lease is None:
            self._tombstones[lease_id] = None  # a cancelled request may still be waiting for its grant
            while len(self._tombstones) > _TOMBSTONES:
                self._tombstones.popitem(last=False)
            return
        if self._tokens is not None and actual_tokens is not None:
            self._tokens.refill(now)
            self._tokens.take(actual_tokens - lease.estimated_tokens)
        if outcome == "ok":
            self.window = min(float(self.limits.max_concurrency), self.window + 1 / self.window)
        elif outcome == "rate_limited":
            self.rate_limited += 1
            # Calls granted before the last decrease saw the old window: one halving per round.
            if lease.granted_at >= self.last_decrease:
                self.window = max(1.0, self.window / 2)
                self.last_decrease = now
                self.decreases += 1
            if retry_after_s:
                self.paused_until = max(self.paused_until, now + retry_after_s)

    def stats(self) -> LimiterStats:
        return LimiterStats(
            window=self.window,
            concurrency=self.concurrency,
            in_flight=self.in_flight,
            granted=self.granted,
            waits=self.waits,
            rate_limited=self.rate_limited,
            decreases=self.decreases,
            reclaimed=self.reclaimed,
        )

    def _reclaim(self, now: float) -> None:
        for lease_id in [key for key, lease in self._leases.items() if lease.expires_at <= now]:
            del self._leases[lease_id]
            self.reclaimed += 1
            logger.warning(
                "rate limiter reclaimed lease %s after %.0f s (its holder never released it)",
                lease_id,
                self.limits.lease_s,
            )


class LocalRateLimiter:
    """The state behind an asyncio lock; waiters wake on release. Run as-is in process, or as a Ray actor."""

    def __init__(self, limits: RateLimits, max_block_s: float = 1.0) -> None:
        self._limits = limits
        self._state = RateLimitState(limits, now=time.monotonic())
        self._changed = asyncio.Condition()
        self._max_block_s = max_block_s

    async def acquire(self, estimated_tokens: int, lease_id: str | None = None) -> Grant | Wait:
        """A grant, or (after blocking at most ``max_block_s``) what to wait for before asking again."""
        deadline = time.monotonic() + self._max_block_s
        async with self._changed:
            while True:
                now = time.monotonic()
                decision = self._state.acquire(estimated_tokens, now, lease_id)
                remaining = deadline - now
                if isinstance(decision, Grant) or remaining <= 0:
                    return decision
                if decision.seconds is not None and decision.seconds > remaining:
                    return Wait(decision.seconds)  # the caller sleeps; no point holding the call open
                timeout = remaining if decision.seconds is None else decision.seconds
                with contextlib.suppress(TimeoutError):
                    await asyncio.wait_for(self._changed.wait(), timeout)

    async def release(
        self, lease_id: str, actual_tokens: int | None, outcome: Outcome, retry_after_s: float | None = None
    ) -> None:
        async with self._changed:
            self._state.release(lease_id, actual_tokens, outcome, time.monotonic(), retry_after_s)
            self._changed.notify_all()

    async def stats(self) -> LimiterStats:
        return self._state.stats()

    async def limits(self) -> RateLimits:
        return self._limits


class RateLimiterActor(LocalRateLimiter):
    """The limiter as a Ray actor (``get_or_create_limiter`` makes it one); one per model key."""


class Slot:
    """A granted call; ``report`` what it cost and whether the provider throttled it."""

    def __init__(self, grant: Grant) -> None:
        self.grant = grant
        self.tokens: int | None = None
        self.outcome: Outcome | None = None
        self.retry_after_s: float | None = None

    def report(self, tokens: int | None, *, rate_limited: bool = False, retry_after_s: float | None = None) -> None:
        self.tokens = tokens
        self.outcome = "rate_limited" if rate_limited else "ok"
        self.retry_after_s = retry_after_s


class RateLimiterHandle(ABC):
    """What a model client holds: slots from a limiter in this process or in a Ray actor."""

    @contextlib.asynccontextmanager
    async def slot(self, estimated_tokens: int) -> AsyncIterator[Slot]:
        """Wait for a slot and hold it for the block; an unreported block that raises counts as an error."""
        lease_id = uuid.uuid4().hex
        try:
            grant = await self._wait_for_grant(estimated_tokens, lease_id)
        except BaseException:
            await self._release_quietly(lease_id, None, "cancelled", None)  # it may be granted after we left
            raise
        slot = Slot(grant)
        outcome: Outcome = "error"
        try:
            yield slot
            outcome = slot.outcome or "ok"
        except asyncio.CancelledError:
            outcome = "cancelled"
            raise
        except BaseException:
            outcome = slot.outcome if slot.outcome == "rate_limited" else "error"
            raise
        finally:
            await self._release_quietly(lease_id, slot.tokens, outcome, slot.retry_after_s)

    async def _wait_for_grant(self, estimated_tokens: int, lease_id: str) -> Grant:
        while True:
            decision = await self._acquire(estimated_tokens, lease_id)
            if isinstance(decision, Grant):
                return decision
            if decision.seconds:
                await asyncio.sleep(decision.seconds)

    async def _release_quietly(
        self, lease_id: str, tokens: int | None, outcome: Outcome, retry_after_s: float | None
    ) -> None:
        try:
            await asyncio.shield(self._release(lease_id, tokens, outcome, retry_after_s))
        except asyncio.CancelledError:
            raise
        except Exception as exc:  # the lease expires on its own; never fail a finished call over it
            logger.warning("could not release rate-limiter lease %s: %s", lease_id, exc)

    @abstractmethod
    async def _acquire(self, estimated_tokens: int, lease_id: str) -> Grant | Wait: ...

    @abstractmethod
    async def _release(
        self, lease_id: str, tokens: int | None, outcome: Outcome, retry_after_s: float | None
    ) -> None: ...

    @abstractmethod
    async def stats(self) -> LimiterStats: ...


class LocalLimiterHandle(RateLimiterHandle):
    """A handle on a limiter in this process (tests, a single-process run)."""

    def __init__(self, limits_or_limiter: RateLimits | LocalRateLimiter) -> None:
        self.limiter = (
            limits_or_limiter
            if isinstance(limits_or_limiter, LocalRateLimiter)
            else LocalRateLimiter(limits_or_limiter)
        )

    async def _acquire(self, estimated_tokens: int, lease_id: str) -> Grant | Wait:
        return await self.limiter.acquire(estimated_tokens, lease_id)

    async def _release(self, lease_id: str, tokens: int | None, outcome: Outcome, retry_after_s: float | None) -> None:
        await self.limiter.release(lease_id, tokens, outcome, retry_after_s)

    async def stats(self) -> LimiterStats:
        return await self.limiter.stats()


@functools.cache
def _actor_class() -> Any:
    import ray

    return ray.remote(RateLimiterActor)


def limiter_name(key: str) -> str:
    return f"llm-limiter:{key}"


class RayLimiterHandle(RateLimiterHandle):
    """A handle on the named limiter actor for ``key``; picklable, so it can be passed to workers."""

    def __init__(self, key: str, limits: RateLimits, namespace: str = LIMITER_NAMESPACE) -> None:
        self.key = key
        self.limits = limits
        self.namespace = namespace
        self._actor: Any = None

    def actor(self) -> Any:
        """The actor, created here if nobody has yet (then it fate-shares with this process)."""
        if self._actor is None:
            self._actor = (
                _actor_class()
                .options(
                    name=limiter_name(self.key),
                    namespace=self.namespace,
                    get_if_exists=True,
                    num_cpus=0,
                    max_concurrency=1000,
                )
                .remote(self.limits)
            )
        return self._actor

    def __getstate__(self) -> dict[str, Any]:
        return {**self.__dict__, "_actor": None}  # resolved by name on the other side

    async def _call(self, method: str, *args: Any) -> Any:
        import ray

        try:
            return await getattr(self.actor(), method).remote(*args)
        except ray.exceptions.RayActorError:
            self._actor = None  # its owner died with it; the next caller re-creates it by name
            return await getattr(self.actor(), method).remote(*args)

    async def _acquire(self, estimated_tokens: int, lease_id: str) -> Grant | Wait:
        return await self._call("acquire", estimated_tokens, lease_id)

    async def _release(self, lease_id: str, tokens: int | None, outcome: Outcome, retry_after_s: float | None) -> None:
        await self._call("release", lease_id, tokens, outcome, retry_after_s)

    async def stats(self) -> LimiterStats:
        return await self._call("stats")


def get_or_create_limiter(key: str, limits: RateLimits, namespace: str = LIMITER_NAMESPACE) -> RayLimiterHandle:
    """The cluster's limiter for ``key``, created now if absent (Ray must be initialised).

    The actor is not detached: it is owned by the process that creates it and dies with it, so
    call this from the sweep's driver first and the limiter lives exactly as long as the sweep.
    Workers calling it later get the same actor (the first creator's limits win).
    """
    handle = RayLimiterHandle(key, limits, namespace)
    handle.actor()
    return handle
