"""Oracle trajectories for any suite: composite calls planned from (initial project, golden project)."""

from scratchworld_dist.kinds.tasks.oracle_plan._planner import (
    PlanRefusedError,
    ProjectPlan,
    plan_project,
    project_differences,
)
from scratchworld_dist.kinds.tasks.oracle_plan._state import ProjectState, read_state
from scratchworld_dist.kinds.tasks.oracle_plan._suite import (
    PLANS_FILE,
    SuitePlans,
    TaskPlan,
    TaskPlanRecord,
    plan_folder,
    plan_suite,
    plan_task,
    planning_suite,
    write_plans,
)

__all__ = [
    "PLANS_FILE",
    "PlanRefusedError",
    "ProjectPlan",
    "ProjectState",
    "SuitePlans",
    "TaskPlan",
    "TaskPlanRecord",
    "plan_folder",
    "plan_project",
    "plan_suite",
    "plan_task",
    "planning_suite",
    "project_differences",
    "read_state",
    "write_plans",
]
