"""The Ray actor behind every worker (one browser, several concurrent jobs of any kind, each handed to its kind),
and the browser it hands to every kind whose jobs open editors. Both need Ray or the browser stack, so they are
imported on first use."""

import typing

import workers

if typing.TYPE_CHECKING:
    from workers.actor._browser import WorkerBrowser
    from workers.actor._job_worker import JobWorker

__getattr__ = workers.lazy_exports(__name__, {"._browser": ("WorkerBrowser",), "._job_worker": ("JobWorker",)})

__all__ = ["JobWorker", "WorkerBrowser"]
