"""A sweep reporting to real trackers that write local folders: an MLflow file store (read back through MLflow's
client) and W&B offline (its run files read back); a resumed run continues the same tracker runs; a tracker that
fails or hangs is said once and neither fails nor holds up the sweep (synthetic episodes on a real local Ray)."""

from __future__ import annotations

import json
import socket
import threading
from collections.abc import Iterator
from pathlib import Path

import pytest
import yaml

from scratchworld_dist.results import read_manifest
from tests.conftest import REPO
from tests.support import wandb_files
from tests.support.sweep_driver import run_here

pytestmark = pytest.mark.ray

TASKS = ["sum_two_numbers", "quiz_score"]
"""Two tasks: ``quiz_score`` fails (synthetic episodes), the other passes."""


@pytest.fixture(autouse=True)
def _mlflow_file_store(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("MLFLOW_ALLOW_FILE_STORE", "true")  # MLflow 3 asks to opt in to its file store


def write_config(tmp_path: Path, loggers: dict[str, object], **fields: object) -> Path:
    config = {
        "name": "tracked",
        "suite": str(REPO / "tasks"),
        "agent": "oracle",
        "output": str(tmp_path / "run"),
        "tasks": {"ids": TASKS},
        "episodes": {"synthetic": {"fail_tasks": ["quiz_score"]}},
        "tags": {"team": "evals"},
        "loggers": {"every_results": 1, **loggers},
        **fields,
    }
    path = tmp_path / "sweep.yaml"
    path.write_text(yaml.safe_dump(config))
    return path


def mlflow_runs(store: Path, experiment: str = "tracked") -> list[object]:
    from mlflow import MlflowClient

    client = MlflowClient(tracking_uri=store.as_uri())
    found = client.get_experiment_by_name(experiment)
    assert found is not None, f"no experiment {experiment} in {store}"
    return client.search_runs([found.experiment_id])


def test_a_sweep_reports_to_mlflow_and_wandb(tmp_path: Path, shared_ray: int) -> None:
    from mlflow import MlflowClient

    store, wandb_dir = tmp_path / "mlruns", tmp_path / "wandb-files"
    loggers = {"mlflow": {"tracking_uri": store.as_uri()}, "wandb": {"mode": "offline", "dir": str(wandb_dir)}}
    code, out = run_here(write_config(tmp_path, loggers), "--progress", "none")
    assert code == 0, out
    assert not [line for line in out.splitlines() if line.startswith(("tracker", "trackers:"))], out

    manifest = read_manifest(tmp_path / "run")
    assert manifest is not None and manifest.trackers is not None
    [run] = mlflow_runs(store)
    assert manifest.trackers.runs == {"mlflow": run.info.run_id, "wandb": manifest.trackers.key}
    assert run.info.status == "FINISHED"
    params = run.data.params
    assert (params["suite_hash"], params["harness"]) == (manifest.suite.hash, manifest.harness.digest)
    assert (params["modes"], params["agent"], params["planned_jobs"]) == ("composite", "oracle", "2")
    assert run.data.tags["tag.team"] == "evals"
    assert run.data.metrics["composite/sr"] == 0.5
    assert run.data.metrics["composite/coverage"] == 1.0
    assert run.data.metrics["composite/psr"] < 1.0
    client = MlflowClient(tracking_uri=store.as_uri())
    decided = sorted((m.step, m.value) for m in client.get_metric_history(run.info.run_id, "decided"))
    assert decided[0] == (0, 0.0) and decided[-1] == (2, 2.0)
    assert (1, 1.0) in decided  # sent as the jobs finished, not only at the end
    artifacts = {a.path for a in client.list_artifacts(run.info.run_id)}
    assert {"report.md", "report.json", "leaderboard.csv", "leaderboard.json"} <= artifacts
    report = client.download_artifacts(run.info.run_id, "report.md", str(tmp_path / "got"))
    assert Path(report).read_text() == (tmp_path / "run" / "report.md").read_text()  # the run's report, as run saved it
    board = json.loads(Path(client.download_artifacts(run.info.run_id, "leaderboard.json", str(tmp_path))).read_text())
    assert [entry["passed"] for entry in board["entries"]] == [1]

    [offline] = wandb_files.offline_runs(wandb_dir)
    assert offline.name == f"run-{manifest.trackers.key}.wandb"
    config = wandb_files.config(offline)
    assert (config["suite_hash"], config["harness"]) == (manifest.suite.hash, manifest.harness.digest)
    logged = wandb_files.history(offline)
    assert logged[-1]["composite/sr"] == 0.5 and logged[-1]["decided"] == 2
    assert {"artifact", "exit"} <= wandb_files.kinds(offline)


def test_a_resumed_run_continues_its_tracker_runs(tmp_path: Path, shared_ray: int) -> None:
    store, wandb_dir = tmp_path / "mlruns", tmp_path / "wandb-files"
    loggers = {"mlflow": {"tracking_uri": store.as_uri()}, "wandb": {"mode": "offline", "dir": str(wandb_dir)}}
    slow = {"synthetic": {"fail_tasks": ["quiz_score"], "duration_s": 2}}
    cut_short = write_config(tmp_path, loggers, episodes=slow, limits={"episode_timeout_s": 0.5, "retries": 0})
    code, out = run_here(cut_short, "--progress", "none")
    assert code == 1, out  # every job timed out: none decided
    first = read_manifest(tmp_path / "run")
    assert first is not None and first.trackers is not None
    [run] = mlflow_runs(store)
    assert run.data.metrics["composite/coverage"] == 0.0
    assert run.data.metrics["composite/cost_usd"] == 0.0
    # As if the driver had died before recording MLflow's run id: the run is found again by its key.
    first.trackers.runs.clear()
    (tmp_path / "run" / "manifest.json").write_text(first.model_dump_json())

    code, out = run_here(write_config(tmp_path, loggers, episodes=slow), "--progress", "none")
    assert code == 0, out
    [resumed] = mlflow_runs(store)
    assert resumed.info.run_id == run.info.run_id
    assert resumed.data.metrics["composite/coverage"] == 1.0
    assert resumed.data.metrics["composite/sr"] == 0.5
    second = read_manifest(tmp_path / "run")
    assert second is not None and second.trackers is not None
    assert second.trackers.key == first.trackers.key
    assert second.trackers.runs["mlflow"] == run.info.run_id
    sessions = wandb_files.offline_runs(wandb_dir)
    assert [path.name for path in sessions] == [f"run-{first.trackers.key}.wandb"] * 2  # one W&B run, two sessions
    assert wandb_files.history(sessions[-1])[-1]["composite/coverage"] == 1.0


@pytest.fixture
def silent_server() -> Iterator[str]:
    """An HTTP address that accepts connections and never answers (a tracking server that hangs)."""
    listener = socket.create_server(("127.0.0.1", 0))
    held: list[socket.socket] = []
    stop = threading.Event()

    def accept() -> None:
        while not stop.is_set():
            try:
                conn, _ = listener.accept()
            except OSError:
                return
            held.append(conn)

    thread = threading.Thread(target=accept, daemon=True)
    thread.start()
    yield f"http://127.0.0.1:{listener.getsockname()[1]}"
    stop.set()
    listener.close()
    for conn in held:
        conn.close()


def test_a_failing_or_hanging_tracker_is_said_once_and_the_sweep_goes_on(
    tmp_path: Path, shared_ray: int, silent_server: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setenv("MLFLOW_HTTP_REQUEST_MAX_RETRIES", "0")
    not_a_folder = tmp_path / "a-file"
    not_a_folder.write_text("")
    loggers = {
        "mlflow": {"tracking_uri": silent_server},
        "wandb": {"mode": "offline", "dir": str(not_a_folder / "wandb")},
        "finish_timeout_s": 1,
    }
    code, out = run_here(write_config(tmp_path, loggers), "--progress", "none")
    assert code == 0, out
    lines = [line for line in out.splitlines() if line.startswith("tracker ")]
    assert len(lines) == 2, out
    assert any(line.startswith("tracker mlflow was still busy 1 s after the run ended") for line in lines), out
    assert any(line.startswith("tracker wandb failed starting its run: ") for line in lines), out
    manifest = read_manifest(tmp_path / "run")
    assert manifest is not None and manifest.trackers is not None and manifest.trackers.runs == {}
    assert "passed 1, failed 1, error 0" in out  # every job decided, as without trackers
