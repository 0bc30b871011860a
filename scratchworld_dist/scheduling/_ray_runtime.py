"""Starting and joining Ray: a private local instance by default, a cluster by address."""

from __future__ import annotations

import os
from collections.abc import Iterator
from contextlib import contextmanager

import ray

from scratchworld_dist._errors import ScratchWorldError

BROWSER_RESOURCE = "browser"
"""Custom resource counting the editors a node may hold; each worker reserves one per page."""

LOCAL_OBJECT_STORE_BYTES = 512 * 2**20
"""Projects and scripts are small; a modest store keeps a laptop's /dev/shm free."""


class RayUnavailableError(ScratchWorldError):
    """Ray could not be started or joined, or offers no browser slots."""


@contextmanager
def ray_runtime(address: str | None, browser_slots: int | None) -> Iterator[int]:
    """Run Ray for the duration of the block; yields the number of browser slots available.

    Without an address a private instance is started (``address='local'``), even when a
    ``ray start`` cluster runs on this machine; with one, that cluster's nodes must declare
    ``--resources='{"browser": N}'``.
    """
    already = ray.is_initialized()
    if not already:
        try:
            if address is None:
                slots = browser_slots or os.cpu_count() or 1
                ray.init(
                    address="local",
                    num_cpus=max(slots, os.cpu_count() or 1),
                    resources={BROWSER_RESOURCE: slots},
                    include_dashboard=False,
                    log_to_driver=False,
                    object_store_memory=LOCAL_OBJECT_STORE_BYTES,
                    configure_logging=False,
                )
            else:
                ray.init(address=address, log_to_driver=False, configure_logging=False)
        except (ConnectionError, ValueError, RuntimeError) as exc:
            raise RayUnavailableError(f"could not start or join Ray ({address or 'local'}): {exc}") from exc
    try:
        total = int(ray.cluster_resources().get(BROWSER_RESOURCE, 0))
        if total < 1:
            raise RayUnavailableError(
                f"the Ray cluster at {address} offers no {BROWSER_RESOURCE!r} resources: start its nodes with "
                f"ray start --resources='{{\"{BROWSER_RESOURCE}\": N}}' (N editors per node)"
            )
        yield total
    finally:
        if not already:
            ray.shutdown()
