"""A per-model circuit breaker: stop calling a provider that keeps failing, try again after a cool-down.

Only calls that failed for good on transient errors (retries exhausted: the provider is down or
throttling hard) count. Any answer from the provider, even a 400, shows it is up and closes the
circuit. While open, calls fail at once with ``ModelCallError("model_circuit_open")``; after the
cool-down a single trial call goes through, and its result closes or re-opens the circuit.
"""

from __future__ import annotations

import logging
import threading
import time
from collections import deque
from collections.abc import Callable
from typing import Literal

from workers.contract import ModelCallError

logger = logging.getLogger(__name__)

BreakerState = Literal["closed", "open", "half_open"]


class CircuitBreaker:
    """Opens after ``failures`` failed calls within ``window_s``; stays open for ``cooldown_s``."""

    def __init__(
        self,
        key: str,
        failures: int = 5,
        window_s: float = 300.0,
        cooldown_s: float = 60.0,
        clock: Callable[[], float] = time.monotonic,
    ) -> None:
        self.key = key
        self.failures = failures
        self.window_s = window_s
        self.cooldown_s = cooldown_s
        self._clock = clock
        self._recent: deque[float] = deque()
        self._opened_at: float | None = None
        self._trial_running = False

    @property
    def state(self) -> BreakerState:
        if self._opened_at is None:
            return "closed"
        if self._clock() - self._opened_at >= self.cooldown_s:
            return "half_open"
        return "open"

    def before_call(self) -> bool:
        """Let a call through (True when it is the half-open trial) or raise ``circuit_open``."""
        state = self.state
        if state == "closed":
            return False
        if state == "half_open" and not self._trial_running:
            self._trial_running = True
            return True
        assert self._opened_at is not None
        wait = max(0.0, self._opened_at + self.cooldown_s - self._clock())
        raise ModelCallError(
            "model_circuit_open",
            f"{self.key}: circuit open after {self.failures} failed calls; next trial in {wait:.0f} s",
            transient=True,
            attempts=0,
        )

    def record_success(self) -> None:
        if self._opened_at is not None:
            logger.info("%s: circuit closed", self.key)
        self._recent.clear()
        self._opened_at = None
        self._trial_running = False

    def record_failure(self) -> None:
        now = self._clock()
        if self._trial_running or self._opened_at is not None:
            self._opened_at = now  # the trial failed: another full cool-down
            self._trial_running = False
            logger.warning("%s: trial call failed, circuit stays open for %.0f s", self.key, self.cooldown_s)
            return
        self._recent.append(now)
        while self._recent and now - self._recent[0] > self.window_s:
            self._recent.popleft()
        if len(self._recent) >= self.failures:
            self._opened_at = now
            self._recent.clear()
            logger.warning(
                "%s: %d calls failed within %.0f s, circuit open for %.0f s",
                self.key,
                self.failures,
                self.window_s,
                self.cooldown_s,
            )

    def record_abandoned(self, trial: bool) -> None:
        """The call ended without a verdict (cancelled): free the trial for the next caller."""
        if trial:
            self._trial_running = False


_BREAKERS: dict[str, CircuitBreaker] = {}
_BREAKERS_LOCK = threading.Lock()


def circuit_breaker(key: str, failures: int = 5, window_s: float = 300.0, cooldown_s: float = 60.0) -> CircuitBreaker:
    """This process's breaker for ``key``, shared by every client of that model (the first settings win)."""
    with _BREAKERS_LOCK:
        breaker = _BREAKERS.get(key)
        if breaker is None:
            breaker = _BREAKERS[key] = CircuitBreaker(key, failures, window_s, cooldown_s)
        return breaker
