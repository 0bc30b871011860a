"""The task-episodes kind (``benchmark: tasks``), the default."""

from scratchworld_dist.kinds.tasks._kind import TASKS, TasksKind, default_episode_clock, offline_sources

__all__ = ["TASKS", "TasksKind", "default_episode_clock", "offline_sources"]
