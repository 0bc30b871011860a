"""Sweeps: the config file, and the job header and naming every kind's planning shares."""

from scratchworld_dist.sweep._config import (
    Limits,
    ModelConfig,
    RayConfig,
    SweepConfig,
    TaskSelection,
    load_sweep_config,
    sweep_config_from,
)
from scratchworld_dist.sweep._former_keys import (
    into_sections,
    moved_keys,
    stderr_notice,
    stored_layout,
    stored_section,
)
from scratchworld_dist.sweep._overrides import SweepOverrides
from scratchworld_dist.sweep._plan import (
    NO_MODEL,
    JobBody,
    JobSpec,
    agent_identity,
    identity_id,
    read_project,
    suite_hash,
)
from scratchworld_dist.sweep._selection import present_suites, wanted_ids

__all__ = [
    "NO_MODEL",
    "JobBody",
    "JobSpec",
    "Limits",
    "ModelConfig",
    "RayConfig",
    "SweepConfig",
    "SweepOverrides",
    "TaskSelection",
    "agent_identity",
    "identity_id",
    "into_sections",
    "load_sweep_config",
    "moved_keys",
    "present_suites",
    "read_project",
    "stderr_notice",
    "stored_layout",
    "stored_section",
    "suite_hash",
    "sweep_config_from",
    "wanted_ids",
]
