"""Memory shared across a sweep's jobs (for learning agents such as AWM): streams, waves, stores, induction.

A learning agent's memory is one store per (model, mode, seed) stream, kept in the run
directory by a Ray actor on the driver's node. Online memory grows in waves (the jobs of wave k
run, then the next snapshot is induced from what they proposed); offline memory is induced once
from a previous run directory's proposals. Each job records the snapshot it saw.
"""

from scratchworld_dist.memory._folder import (
    MEMORY_DIR,
    JobItems,
    MemoryFolder,
    SnapshotRecord,
    StoreInfo,
    learnable,
    offline_source,
    source_digest,
)
from scratchworld_dist.memory._keeper import MemoryKeeper, start_memory_service
from scratchworld_dist.memory._waves import induction_seed, store_name, task_waves

__all__ = [
    "MEMORY_DIR",
    "JobItems",
    "MemoryFolder",
    "MemoryKeeper",
    "SnapshotRecord",
    "StoreInfo",
    "induction_seed",
    "learnable",
    "offline_source",
    "source_digest",
    "start_memory_service",
    "store_name",
    "task_waves",
]
