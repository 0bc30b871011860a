"""``scratchworld regrade``: a run's stored final projects evaluated again under other conditions."""

from scratchworld_dist.kinds.tasks.regrade._plan import RegradeJob, RegradePlan, plan_regrade, regrade_job_id
from scratchworld_dist.kinds.tasks.regrade._run import RegradeSummary, run_regrade
from scratchworld_dist.kinds.tasks.regrade._source import SourceJob, SourceRun, read_source

__all__ = [
    "RegradeJob",
    "RegradePlan",
    "RegradeSummary",
    "SourceJob",
    "SourceRun",
    "plan_regrade",
    "read_source",
    "regrade_job_id",
    "run_regrade",
]
