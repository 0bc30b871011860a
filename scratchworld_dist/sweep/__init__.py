"""Sweeps: the config file and the job matrix it plans."""

from scratchworld_dist.sweep._config import (
    Limits,
    ModelConfig,
    RayConfig,
    SweepConfig,
    TaskSelection,
    load_sweep_config,
)
from scratchworld_dist.sweep._plan import (
    NO_MODEL,
    JobSpec,
    TaskContent,
    identity_id,
    job_id,
    plan_jobs,
    read_project,
    read_task,
    suite_hash,
)

__all__ = [
    "NO_MODEL",
    "JobSpec",
    "Limits",
    "ModelConfig",
    "RayConfig",
    "SweepConfig",
    "TaskContent",
    "TaskSelection",
    "identity_id",
    "job_id",
    "load_sweep_config",
    "plan_jobs",
    "read_project",
    "read_task",
    "suite_hash",
]
