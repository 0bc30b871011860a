"""How many episodes this machine runs at once when the sweep does not say: admission by measured cost.

Jobs whose agent calls a model spend most of their time waiting on the provider, so a node holds
as many of them as its CPU (what a waiting page burns, measured) and its memory (one editor's
PSS, measured) allow, less a margin, and never more than the node delivers in their mode (primitive
if any job's is: its steps cost the browser far more; ``workers.node.derive_slots``). Jobs without a model keep
their page busy: one per core, as before. Either way the episodes are spread over one worker (one
browser) per core. Jobs that open no editor (perception questions about a static screenshot) cost
the node nothing while they wait. Explicit ``browser_slots`` and ``pages_per_worker`` win over all of this,
except for jobs a person works on (``exclusive`` agents): one at a time.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Sequence

from scratchworld_dist.sweep import JobSpec, Limits
from workers.agent_api import agent_class
from workers.contract import MIB, AgentUnavailableError, ClockMode, Mode
from workers.editor import cached_editor_cost
from workers.node import DELIVERED_PER_CORE, SlotDerivation, derive_slots, node_memory

BROWSERLESS_PER_CORE = 8
"""Slots per core for jobs that open no editor and wait on a model (perception): a waiting call costs no CPU, so
the model's rate limits, not the node, bound them."""


def waiting_clock(jobs: Sequence[JobSpec]) -> ClockMode | None:
    """The clock whose waiting pages bound the node (real if any job runs on it); None when no job waits on a model."""
    waiting = [job for job in jobs if job.model is not None]
    if not waiting:
        return None
    return "real" if any(job.body.page_clock == "real" for job in waiting) else "virtual"


def waiting_mode(jobs: Sequence[JobSpec]) -> Mode:
    """The mode whose steps bound what the node delivers: primitive if any job waiting on a model runs in it."""
    return "primitive" if any(job.model is not None and job.mode == "primitive" for job in jobs) else "composite"


def admitted_slots(limits: Limits, jobs: Sequence[JobSpec], harness: str, say: Callable[[str], None]) -> int:
    """Browser slots for a private local Ray: as configured, else derived from this machine (jobs that open no
    editor and wait on a model: ``BROWSERLESS_PER_CORE`` per core)."""
    if exclusive(jobs):
        say("admission: 1 browser slot (a person works on each job: one at a time, on this machine)")
        return 1
    if limits.browser_slots is not None:
        return limits.browser_slots
    cores = os.cpu_count() or 1
    if not any(job.needs_browser for job in jobs):
        return cores * (BROWSERLESS_PER_CORE if any(job.model is not None for job in jobs) else 1)
    clock = waiting_clock(jobs)
    if clock is None:
        return cores
    derivation = derive_local(limits, clock, harness, cores, waiting_mode(jobs))
    say(f"admission: {derivation.describe()} (limits.browser_slots overrides)")
    return derivation.slots


def most_slots(limits: Limits, cores: int) -> int:
    """The most browser slots ``admitted_slots`` gives this machine, whatever the jobs: what a private Ray started
    before the jobs are settled (beside the preflight) must offer."""
    if limits.browser_slots is not None:
        return limits.browser_slots
    return cores * max(DELIVERED_PER_CORE, BROWSERLESS_PER_CORE)


def exclusive(jobs: Sequence[JobSpec]) -> bool:
    """Whether some job's agent takes the whole node (``exclusive``: a person at the screen)."""
    for name, kind in {(job.agent.name, job.body.kind) for job in jobs}:
        try:
            if getattr(agent_class(name, kind), "exclusive", False):
                return True
        except AgentUnavailableError:
            continue  # the preflight names an agent this machine lacks
    return False


def derive_local(
    limits: Limits, clock: ClockMode, harness: str, cores: int, mode: Mode = "composite"
) -> SlotDerivation:
    return derive_slots(
        cached_editor_cost(clock, harness),
        cores=cores,
        memory=node_memory(),
        margin=limits.capacity_margin,
        reserve_bytes=limits.memory_reserve_mb * MIB,
        mode=mode,
    )


def pages_per_worker(limits: Limits, slots: int, cores: int) -> int:
    """Pages per worker: as configured, else the slots spread over one worker per core."""
    if limits.pages_per_worker is not None:
        return limits.pages_per_worker
    return max(1, slots // max(cores, 1))
