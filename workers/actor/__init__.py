"""The Ray actor behind every worker: one browser, several concurrent jobs of any kind, each handed to its kind."""

from workers.actor._job_worker import JobWorker

__all__ = ["JobWorker"]
