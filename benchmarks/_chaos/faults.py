"""The fault schedule, drawn from the seed, and the injector that carries it out.

The schedule says what happens after how many committed attempts (rows in the run directory):
progress, not wall time, so the same seed gives the same schedule on any machine. Which process
a fault hits is drawn from the same seeded RNG among the candidates alive at that moment. A
fault whose kind has no candidate yet (no Chromium open, workers still starting) waits for one.
"""

from __future__ import annotations

import os
import random
import signal
import time
from collections import Counter
from typing import Literal

from pydantic import BaseModel

from _chaos.cluster import LocalCluster, Proc

FaultKind = Literal["driver", "worker", "renderer", "browser"]


class Fault(BaseModel):
    """One planned fault."""

    kind: FaultKind
    after: int
    """Fire once the run directory holds this many committed attempts."""


class FaultRecord(BaseModel):
    """One fault as it happened."""

    at_s: float
    """Seconds since the benchmark started."""

    kind: FaultKind
    target: str
    committed: int
    """Committed attempts when it fired."""


def plan_faults(seed: int, planned_jobs: int, drivers: int, workers: int, chromium: int) -> list[Fault]:
    """The schedule: thresholds spread over 5-70% of the planned jobs, kinds in a seeded order.

    Each Chromium fault kills a renderer (one page) or the browser (all pages of a worker), by the seed.
    """
    rng = random.Random(seed)
    kinds: list[FaultKind] = ["driver"] * drivers + ["worker"] * workers
    kinds += [rng.choice(("renderer", "browser")) for _ in range(chromium)]
    rng.shuffle(kinds)
    low, high = max(1, planned_jobs * 5 // 100), max(planned_jobs * 70 // 100, len(kinds) + 2)
    thresholds = sorted(rng.sample(range(low, high), len(kinds)))
    return [Fault(kind=kind, after=after) for kind, after in zip(kinds, thresholds, strict=True)]


class Injector:
    """Fires the scheduled faults at the cluster's processes; the driver is killed by the caller's callback."""

    def __init__(self, seed: int, cluster: LocalCluster, started: float) -> None:
        self._rng = random.Random(seed + 1)
        self.cluster = cluster
        self.started = started
        self.log: list[FaultRecord] = []

    def targets(self, kind: FaultKind) -> list[Proc]:
        """Candidates, in a stable order: busy worker actors first choice, Chromium of any worker."""
        if kind == "worker":
            actors = self.cluster.worker_actors()
            busy = [p for p in actors if ".run" in p.cmdline]  # Ray titles a process by its running method
            return sorted(busy or actors, key=lambda p: p.pid)
        if kind in ("renderer", "browser"):
            return sorted(self.cluster.chromium(kind), key=lambda p: p.pid)
        raise ValueError(kind)

    def kill(self, kind: FaultKind, committed: int) -> bool:
        """SIGKILL one process of ``kind``; False when there is none yet (the caller tries again)."""
        candidates = self.targets(kind)
        if not candidates:
            return False
        victim = self._rng.choice(candidates)
        try:
            os.kill(victim.pid, signal.SIGKILL)
        except ProcessLookupError:
            return False  # it ended on its own meanwhile
        self.record(kind, f"pid {victim.pid} {victim.cmdline[:60]}", committed)
        return True

    def record(self, kind: FaultKind, target: str, committed: int) -> None:
        record = FaultRecord(at_s=time.monotonic() - self.started, kind=kind, target=target, committed=committed)
        self.log.append(record)
        print(f"  {record.at_s:7.1f} s  fault: {kind} ({target}) after {committed} committed attempts", flush=True)

    def fired(self) -> Counter[str]:
        return Counter(record.kind for record in self.log)
