"""Scheduling on Ray: the runtime, the nodes' agreement on one harness, the models' preflight, admission, the
worker pool, the driver loop and its progress line."""

from scratchworld_dist.scheduling._admission import (
    admitted_slots,
    derive_local,
    exclusive,
    most_slots,
    pages_per_worker,
)
from scratchworld_dist.scheduling._node_watch import LostNode, NodeWatch
from scratchworld_dist.scheduling._nodes import agreed_harness, inspect_nodes
from scratchworld_dist.scheduling._pool import WorkerPool
from scratchworld_dist.scheduling._preflight import (
    ModelCalls,
    PreflightError,
    broken_by_settings,
    broken_line,
    refuse_broken,
    run_preflight,
    settle,
)
from scratchworld_dist.scheduling._progress import (
    PROGRESS_MODES,
    ProgressMode,
    ProgressOptions,
    live_progress,
    shown_mode,
)
from scratchworld_dist.scheduling._ray_runtime import (
    BROWSER_RESOURCE,
    RayUnavailableError,
    ray_runtime,
    worker_logs_dir,
)
from scratchworld_dist.scheduling._scheduler import Scheduler, SchedulerStats, SchedulerWatcher

__all__ = [
    "BROWSER_RESOURCE",
    "PROGRESS_MODES",
    "LostNode",
    "ModelCalls",
    "NodeWatch",
    "PreflightError",
    "ProgressMode",
    "ProgressOptions",
    "RayUnavailableError",
    "Scheduler",
    "SchedulerStats",
    "SchedulerWatcher",
    "WorkerPool",
    "admitted_slots",
    "agreed_harness",
    "broken_by_settings",
    "broken_line",
    "derive_local",
    "exclusive",
    "inspect_nodes",
    "live_progress",
    "most_slots",
    "pages_per_worker",
    "ray_runtime",
    "refuse_broken",
    "run_preflight",
    "settle",
    "shown_mode",
    "worker_logs_dir",
]
