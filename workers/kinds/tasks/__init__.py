"""The ``tasks`` kind inside a worker: multi-step episodes (an agent acting in an environment until it stops, then
the evaluation), and regrades of the projects they left (the evaluation alone, in the same recycled editors); their
jobs as the driver sends them are ``EpisodeSpec`` and ``RegradeSpec``.

The runner and environments need the browser stack, so they are imported on first use: importing this package
(what the kind registry does) stays light.
"""

import typing

import workers
from workers.kinds.tasks._contract import EpisodeSpec, RegradeSpec
from workers.kinds.tasks._kind import REGRADED, TASKS, TasksKind

if typing.TYPE_CHECKING:
    from workers.kinds.tasks._environment import CompositeEnvironment, Environment, PrimitiveEnvironment
    from workers.kinds.tasks._runner import EpisodeRunner
    from workers.kinds.tasks._synthetic import run_synthetic

__getattr__ = workers.lazy_exports(
    __name__,
    {
        "._environment": ("CompositeEnvironment", "Environment", "PrimitiveEnvironment"),
        "._runner": ("EpisodeRunner",),
        "._synthetic": ("run_synthetic",),
    },
)

__all__ = [
    "REGRADED",
    "TASKS",
    "CompositeEnvironment",
    "Environment",
    "EpisodeRunner",
    "EpisodeSpec",
    "PrimitiveEnvironment",
    "RegradeSpec",
    "TasksKind",
    "run_synthetic",
]
