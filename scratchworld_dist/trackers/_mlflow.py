"""The MLflow tracker (``loggers: {mlflow: ...}``), through ``MlflowClient``: nothing global is set, so the user's
own MLflow use in the same process is left alone. Needs the ``mlflow`` extra (``mlflow-skinny``)."""

from __future__ import annotations

import time
from typing import Any

from scratchworld_dist.sweep._loggers import MLflowLogger
from scratchworld_dist.trackers._tracker import RunInfo

RUN_KEY_TAG = "scratchworld.run_key"
"""The tag that finds the run directory's MLflow run again (``TrackerRuns.key``)."""

MAX_PARAM_CHARS = 6000
"""MLflow's limit on a parameter's value."""

_STATUS = {"finished": "FINISHED", "interrupted": "KILLED", "failed": "FAILED"}


class MLflowTracker:
    name = "mlflow"

    def __init__(self, settings: MLflowLogger) -> None:
        self.settings = settings
        self.client: Any = None
        self.run_id = ""

    def start(self, run: RunInfo) -> str:
        from mlflow import MlflowClient  # the extra, imported only for a run that logs to MLflow
        from mlflow.entities import Param, RunStatus

        self.client = client = MlflowClient(tracking_uri=self.settings.tracking_uri)
        name = self.settings.experiment or run.name
        experiment = client.get_experiment_by_name(name)
        experiment_id = experiment.experiment_id if experiment is not None else client.create_experiment(name)
        tags = {RUN_KEY_TAG: run.key, **{f"tag.{k}": v for k, v in run.tags.items()}}
        run_id = run.run_ids.get(self.name) or self._found(experiment_id, run.key)
        if run_id is None:
            created = client.create_run(experiment_id, tags=tags, run_name=self.settings.run_name or run.name)
            run_id = created.info.run_id
        else:
            client.update_run(run_id, status=RunStatus.to_string(RunStatus.RUNNING))
            for key, value in tags.items():
                client.set_tag(run_id, key, value)
        self.run_id = run_id
        params = [Param(key, value[:MAX_PARAM_CHARS]) for key, value in run.params.items()]
        client.log_batch(run_id, params=params)  # the same values again on a resumed run
        return run_id

    def _found(self, experiment_id: str, key: str) -> str | None:
        """The run of an earlier session that died before recording MLflow's id, by its key tag."""
        runs = self.client.search_runs([experiment_id], filter_string=f"tags.`{RUN_KEY_TAG}` = '{key}'", max_results=1)
        return runs[0].info.run_id if runs else None

    def log_metrics(self, metrics: dict[str, float], step: int) -> None:
        from mlflow.entities import Metric

        stamp = int(time.time() * 1000)
        self.client.log_batch(self.run_id, metrics=[Metric(k, v, stamp, step) for k, v in metrics.items()])

    def log_artifacts(self, files: dict[str, bytes]) -> None:
        for name, content in files.items():
            self.client.log_text(self.run_id, content.decode("utf-8"), name)

    def finish(self, status: str) -> None:
        self.client.set_terminated(self.run_id, status=_STATUS.get(status, "FINISHED"))
