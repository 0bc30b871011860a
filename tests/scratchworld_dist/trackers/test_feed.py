"""The feed between a run's events and a tracker, on a real MLflow file store: metrics sent every N attempts and
at the end, the end's files attached; a tracker whose URI cannot be used is said once and the feed goes on."""

from __future__ import annotations

from pathlib import Path

import pytest

from scratchworld_dist.sweep._loggers import Loggers, MLflowLogger
from scratchworld_dist.trackers import PlannedJob, RunInfo, TrackerFeed
from scratchworld_dist.trackers._mlflow import MLflowTracker
from tests.support.run_events import finish

PLANNED = {f"j{n}": PlannedJob("m", "composite", "create") for n in range(5)}
RUN = RunInfo(name="fed", key="0123456789abcdef", params={"suite_hash": "abc"}, tags={"team": "evals"})


@pytest.fixture(autouse=True)
def _mlflow_file_store(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("MLFLOW_ALLOW_FILE_STORE", "true")


def test_metrics_go_every_n_attempts_and_at_the_end(tmp_path: Path) -> None:
    from mlflow import MlflowClient

    store = (tmp_path / "mlruns").as_uri()
    said: list[str] = []
    loggers = Loggers(mlflow=MLflowLogger(tracking_uri=store), every_results=2, every_s=3600)
    earlier = [finish("j0", "passed", 1, 1)]  # an earlier session's verdict: the curve starts from it
    feed = TrackerFeed([MLflowTracker(loggers.mlflow)], RUN, PLANNED, earlier, loggers, said.append)  # type: ignore[arg-type]
    for n in range(1, 4):
        feed.hear(finish(f"j{n}", "passed" if n % 2 else "failed", 1, 2))
    runs = feed.finish("finished", lambda: {"report.md": b"# fed\n"})
    assert said == []
    client = MlflowClient(tracking_uri=store)
    [run] = client.search_runs([client.get_experiment_by_name("fed").experiment_id])
    assert runs == {"mlflow": run.info.run_id}
    steps = sorted(m.step for m in client.get_metric_history(run.info.run_id, "decided"))
    assert steps == [1, 3, 4]  # at the start (with the earlier verdict), after 2 attempts, at the end
    assert run.data.metrics["composite/sr"] == 0.75 and run.data.metrics["composite/coverage"] == 0.8
    assert (run.data.params["suite_hash"], run.data.tags["tag.team"]) == ("abc", "evals")
    assert [a.path for a in client.list_artifacts(run.info.run_id)] == ["report.md"]


def test_a_tracker_that_cannot_start_is_said_once(tmp_path: Path) -> None:
    said: list[str] = []
    loggers = Loggers(mlflow=MLflowLogger(tracking_uri="nosuchstore://here"), every_results=1)
    feed = TrackerFeed([MLflowTracker(loggers.mlflow)], RUN, PLANNED, [], loggers, said.append)  # type: ignore[arg-type]
    for n in range(5):
        feed.hear(finish(f"j{n}", "passed", 1, 1))
    assert feed.finish("finished", dict) == {}
    assert len(said) == 1 and said[0].startswith("tracker mlflow failed starting its run: "), said
    assert said[0].endswith("; the run goes on without it")
