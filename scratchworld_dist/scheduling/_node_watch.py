"""Nodes that leave the cluster during a run, named as they go.

Ray's GCS declares a node dead once it misses its health checks: its raylet crashed, its machine went
down, or its network link did (a partition). The node's workers then fail their calls (``RayActorError``)
and the scheduler sends their jobs to other workers; but Ray's errors name an actor ("the actor was
restarted"), not what happened to it. This watch keeps which node each worker is on and reads the node
table now and then, so that the run's log says which node left, at which address, why Ray dropped it, and
which workers it took along.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from typing import Any

import ray
from ray.exceptions import RayError

from workers.contract import WorkerInfo

NODE_CHECK_S = 2.0
"""How often the node table is read while jobs run (each read is one small call to the head)."""


@dataclass(frozen=True)
class LostNode:
    """A node that was alive when the run saw it last, and no longer is."""

    node_id: str
    address: str
    hostname: str
    reason: str
    """Ray's own words for why it dropped the node (e.g. its health checks failed)."""

    workers: tuple[int, ...]
    """The run's workers that were on it when it was lost."""

    @property
    def name(self) -> str:
        return f"{self.hostname} ({self.address}, node {self.node_id[:8]})"


class NodeWatch:
    """Which node each worker is on, and which nodes have left since the run began."""

    def __init__(self) -> None:
        self._alive: dict[str, dict[str, Any]] = {}
        self._where: dict[int, ray.ObjectRef | str] = {}
        """A worker's node id, or the pending ``info`` call that will tell it."""
        self.lost: dict[str, LostNode] = {}
        self._checked = 0.0
        self.check(force=True)

    def locate(self, worker: int, where: ray.ObjectRef | WorkerInfo) -> None:
        """Where ``worker`` is: its ``info()`` call (read once it answers), or its answer."""
        self._where[worker] = where.node_id if isinstance(where, WorkerInfo) else where

    def node_of(self, worker: int) -> str | None:
        """The node ``worker`` was last seen on, when it has said so."""
        where = self._where.get(worker)
        if where is None or isinstance(where, str):
            return where
        ready, _ = ray.wait([where], timeout=0)
        if not ready:
            return None
        try:
            info: WorkerInfo = ray.get(where)
        except RayError:  # it died before it answered: its node is not known
            del self._where[worker]
            return None
        self._where[worker] = info.node_id
        return info.node_id

    def lost_with(self, worker: int) -> LostNode | None:
        """The lost node ``worker`` was on, if its node is lost."""
        node = self.node_of(worker)
        return self.lost.get(node) if node is not None else None

    def check(self, force: bool = False) -> list[LostNode]:
        """The nodes lost since the last check (read at most every ``NODE_CHECK_S``, unless ``force``)."""
        now = time.monotonic()
        if not force and now - self._checked < NODE_CHECK_S:
            return []
        self._checked = now
        try:
            nodes = ray.nodes()
        except (RayError, RuntimeError, OSError):  # the head did not answer: look again next time
            return []
        gone = [node for node in nodes if not node.get("Alive") and node["NodeID"] in self._alive]
        self._alive = {node["NodeID"]: node for node in nodes if node.get("Alive")}
        if not gone:
            return []
        for worker in list(self._where):
            self.node_of(worker)  # settle what can be settled before naming the workers
        found = []
        for node in gone:
            workers = tuple(sorted(w for w, where in self._where.items() if where == node["NodeID"]))
            lost = LostNode(
                node_id=node["NodeID"],
                address=node.get("NodeManagerAddress") or "?",
                hostname=node.get("NodeManagerHostname") or "?",
                reason=(node.get("DeathReasonMessage") or "no reason given").strip(),
                workers=workers,
            )
            self.lost[lost.node_id] = lost
            found.append(lost)
        return found
