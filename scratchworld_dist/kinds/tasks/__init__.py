"""The task-episodes kind (``benchmark: tasks``), the default: planning episodes on a task suite; its report, plots
and comparisons are in ``report``.

Its names are imported on first use (``workers.lazy_exports``): the command line imports its command modules,
inside this package, without loading the kind."""

import typing

import workers

if typing.TYPE_CHECKING:
    from scratchworld_dist.kinds.tasks._kind import (
        TASKS,
        TasksKind,
        default_episode_clock,
        episode_settings,
        offline_sources,
        selected_tasks,
    )
    from scratchworld_dist.kinds.tasks._plan import (
        EpisodeBody,
        EpisodeMatrix,
        TaskContent,
        job_id,
        plan_jobs,
        read_task,
    )
    from scratchworld_dist.kinds.tasks._settings import EPISODES_KEY, EpisodeSweep

__getattr__ = workers.lazy_exports(
    __name__,
    {
        "._kind": (
            "TASKS",
            "TasksKind",
            "default_episode_clock",
            "episode_settings",
            "offline_sources",
            "selected_tasks",
        ),
        "._plan": (
            "EpisodeBody",
            "EpisodeMatrix",
            "TaskContent",
            "job_id",
            "plan_jobs",
            "read_task",
        ),
        "._settings": (
            "EPISODES_KEY",
            "EpisodeSweep",
        ),
    },
)

__all__ = [
    "EPISODES_KEY",
    "TASKS",
    "EpisodeBody",
    "EpisodeMatrix",
    "EpisodeSweep",
    "TaskContent",
    "TasksKind",
    "default_episode_clock",
    "episode_settings",
    "job_id",
    "offline_sources",
    "plan_jobs",
    "read_task",
    "selected_tasks",
]
