"""The pool of worker actors, sized by the cluster's browser slots, kept warm between a process's sweeps."""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass

import ray
from ray import ObjectRef
from ray.actor import ActorHandle

from scratchworld_dist.scheduling._ray_runtime import BROWSER_RESOURCE, RayUnavailableError
from workers.actor import JobWorker
from workers.contract import SyntheticEpisodes


@dataclass
class _KeptWorkers:
    key: tuple[str, int, str, int]
    """The Ray node this process is attached to, then what the workers were built with."""
    handles: list[ActorHandle]


_kept: _KeptWorkers | None = None
"""The last sweep's workers, idle, their browsers and editors open, for this process's next sweep."""


class WorkerPool:
    """One actor per browser; each reserves ``pages`` browser slots and runs that many episodes.

    Actors restart without limit when their process dies (their constructor re-runs and the
    browser is relaunched on first use); calls are never retried by Ray, the driver decides.

    A pool closed with ``keep`` leaves its workers running for the next pool this process makes on
    the same Ray with the same pages, synthetic episodes and memory reserve: that sweep starts on
    warm browsers and recycled editors (checked clean, as between a sweep's own episodes) instead
    of new processes. Any other pool kills them first, so kept workers never hold browser slots it
    needs. Only a driver that runs several sweeps in one process gains (a notebook, the test suite);
    ``scratchworld run`` exits after its sweep, and its workers with it.
    """

    def __init__(
        self,
        browser_slots: int,
        pages: int,
        synthetic: SyntheticEpisodes | None,
        memory_reserve_bytes: int = 0,
        at_once: int | None = None,
    ) -> None:
        """``memory_reserve_bytes``: a worker declines new jobs while its node has less memory available.
        ``at_once``: the most jobs the run will have in flight; no more workers start than hold them
        (each would launch a browser and open editors that a one-job run never uses)."""
        if browser_slots < pages:
            raise RayUnavailableError(
                f"a worker needs {pages} browser slot(s) (pages_per_worker) but the cluster offers {browser_slots}"
            )
        self.pages = pages
        count = browser_slots // pages
        if at_once is not None:
            count = min(count, max(1, math.ceil(at_once / pages)))
        self._key = (
            ray.get_runtime_context().get_node_id(),
            pages,
            synthetic.model_dump_json() if synthetic is not None else "",
            memory_reserve_bytes,
        )
        kept = _take_kept(self._key)
        for handle in kept[count:]:
            ray.kill(handle, no_restart=True)
        self.reused = min(len(kept), count)
        """Workers taken over from this process's previous sweep."""
        actor_class = ray.remote(JobWorker).options(
            resources={BROWSER_RESOURCE: pages},
            num_cpus=0,
            max_restarts=-1,
            max_task_retries=0,
            max_concurrency=pages + 4,
        )
        self.handles: list[ActorHandle] = kept[:count] + [
            actor_class.remote(index, synthetic, memory_reserve_bytes) for index in range(self.reused, count)
        ]
        self._ahead: dict[int, ObjectRef] = {}
        """Warm calls made by ``warm_ahead``, for the scheduler's first ``warm`` to take over."""

    def __len__(self) -> int:
        return len(self.handles)

    def capacity(self, max_in_flight: int | None) -> int:
        """The most jobs the pool runs at once: a page each, and no more than ``max_in_flight``."""
        return min(max_in_flight or len(self) * self.pages, len(self) * self.pages)

    def warm(
        self, workers: Iterable[int], jobs: int, capacity: int, open_editors: bool, calls_models: bool
    ) -> dict[int, ObjectRef]:
        """Have each of ``workers`` open the editors for its share of ``jobs`` (of which ``capacity`` run at
        once) before its first job, and import LiteLLM when jobs call models (``JobWorker.warm``); a worker
        whose warm call ``warm_ahead`` made already keeps that one. Answers each worker's call."""
        editors = min(self.pages, math.ceil(min(jobs, capacity) / len(self))) if open_editors else 0
        calls: dict[int, ObjectRef] = {}
        for worker in workers:
            ahead = self._ahead.pop(worker, None)
            calls[worker] = ahead if ahead is not None else self.handles[worker].warm.remote(editors, calls_models)
        return calls

    def warm_ahead(self, jobs: int, max_in_flight: int | None, open_editors: bool, calls_models: bool) -> None:
        """Start every worker's ``warm`` now, before the scheduler that will run ``jobs`` exists (a sweep's
        workers open their editors while its preflight waits on a model); that scheduler's first ``warm`` takes
        these calls over instead of making its own (in a sweep of memory waves they open the editors for all its
        jobs, not only the first wave's; the later waves use the rest)."""
        self._ahead = self.warm(range(len(self)), jobs, self.capacity(max_in_flight), open_editors, calls_models)

    def describe(self, browser_slots: int) -> str:
        """The line a run prints about its workers."""
        kept = f", {self.reused} kept warm from this process's last sweep" if self.reused else ""
        return f"{len(self)} worker(s) x {self.pages} page(s) on {browser_slots} browser slot(s){kept}"

    def restart(self, index: int) -> None:
        """Kill a worker that stopped answering; Ray starts it again and its calls fail over."""
        ray.kill(self.handles[index], no_restart=False)

    def close(self, keep: bool = False) -> None:
        """Kill the workers, or with ``keep`` leave them for this process's next sweep (only when no
        job of this sweep still runs on them)."""
        global _kept
        if keep:
            _kill_kept()
            _kept = _KeptWorkers(self._key, self.handles)
        else:
            for handle in self.handles:
                ray.kill(handle, no_restart=True)


def _take_kept(key: tuple[str, int, str, int]) -> list[ActorHandle]:
    """The kept workers if they were built like ``key`` asks; kept workers of another kind are killed."""
    global _kept
    if _kept is not None and _kept.key == key:
        handles, _kept = _kept.handles, None
        return handles
    _kill_kept()
    return []


def _kill_kept() -> None:
    global _kept
    kept, _kept = _kept, None
    if kept is not None and kept.key[0] == ray.get_runtime_context().get_node_id():
        for handle in kept.handles:  # (those of a Ray since shut down went with it)
            ray.kill(handle, no_restart=True)
