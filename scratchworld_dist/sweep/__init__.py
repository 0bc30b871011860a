"""Sweeps: the config file, the job header and naming every kind's planning shares, and planning a run
(``plan_run``) through the kind's planning facet (``KindConfig``, ``KindPlanning``)."""

from scratchworld_dist.sweep._config import (
    KindConfig,
    Limits,
    ModelConfig,
    RayConfig,
    SweepConfig,
    TaskSelection,
    load_sweep_config,
    sweep_config_from,
)
from scratchworld_dist.sweep._former_keys import (
    Notice,
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
from scratchworld_dist.sweep._run_plan import (
    ItemContent,
    KindPlanning,
    RunPlan,
    SuiteInfo,
    first_items,
    plan_run,
    sampled_items,
    worker_job,
)
from scratchworld_dist.sweep._selection import present_suites, wanted_ids
from scratchworld_dist.sweep._step_tokens import DEFAULT_RATES, TokenRates

__all__ = [
    "DEFAULT_RATES",
    "NO_MODEL",
    "ItemContent",
    "JobBody",
    "JobSpec",
    "KindConfig",
    "KindPlanning",
    "Limits",
    "ModelConfig",
    "Notice",
    "RayConfig",
    "RunPlan",
    "SuiteInfo",
    "SweepConfig",
    "SweepOverrides",
    "TaskSelection",
    "TokenRates",
    "agent_identity",
    "first_items",
    "identity_id",
    "into_sections",
    "load_sweep_config",
    "moved_keys",
    "plan_run",
    "present_suites",
    "read_project",
    "sampled_items",
    "stderr_notice",
    "stored_layout",
    "stored_section",
    "suite_hash",
    "sweep_config_from",
    "wanted_ids",
    "worker_job",
]
