"""The pool of worker actors, sized by the cluster's browser slots."""

from __future__ import annotations

import math

import ray
from ray.actor import ActorHandle

from scratchworld_dist.scheduling._ray_runtime import BROWSER_RESOURCE, RayUnavailableError
from workers.contract import SyntheticEpisodes
from workers.episode import EpisodeWorker


class WorkerPool:
    """One actor per browser; each reserves ``pages`` browser slots and runs that many episodes.

    Actors restart without limit when their process dies (their constructor re-runs and the
    browser is relaunched on first use); calls are never retried by Ray, the driver decides.
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
        actor_class = ray.remote(EpisodeWorker).options(
            resources={BROWSER_RESOURCE: pages},
            num_cpus=0,
            max_restarts=-1,
            max_task_retries=0,
            max_concurrency=pages + 4,
        )
        self.handles: list[ActorHandle] = [
            actor_class.remote(index, synthetic, memory_reserve_bytes) for index in range(count)
        ]

    def __len__(self) -> int:
        return len(self.handles)

    def restart(self, index: int) -> None:
        """Kill a worker that stopped answering; Ray starts it again and its calls fail over."""
        ray.kill(self.handles[index], no_restart=False)

    def close(self) -> None:
        for handle in self.handles:
            ray.kill(handle, no_restart=True)
