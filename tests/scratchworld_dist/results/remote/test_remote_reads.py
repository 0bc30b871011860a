"""Reading a run directory on object storage in place: a sweep written to a real S3 API server (moto's, on
127.0.0.1), then ``status``, ``report``, ``view`` (served and ``--export``), ``compare``, ``export``, ``regrade``'s
source and ``api.load_results`` on its URL. Only the small files and the artifacts a reader opens are fetched."""

from __future__ import annotations

import re
import subprocess
import urllib.request
from pathlib import Path

import pytest
import yaml

from scratchworld_dist.api import load_results
from scratchworld_dist.kinds.tasks.regrade._source import read_source
from scratchworld_dist.results import RunStore
from scratchworld_dist.results.remote._location import parse_location
from scratchworld_dist.results.remote._view import open_view
from tests.conftest import REPO
from tests.support.cli_runner import invoke
from tests.support.perception_suites import write_suite
from tests.support.records import episode, record, spec
from tests.support.run_dirs import make_run
from tests.support.s3_server import CREDENTIALS, S3Server
from tests.support.sweep_driver import SCRATCHWORLD, run_here
from workers.contract import HarnessFingerprint

pytestmark = pytest.mark.ray


@pytest.fixture(scope="module")
def written(tmp_path_factory: pytest.TempPathFactory, s3: S3Server, shared_ray: int) -> tuple[str, Path]:
    """A perception sweep of the oracle agent (8 jobs) written to ``s3://<bucket>/sweeps/p``; its URL and mirror."""
    folder = tmp_path_factory.mktemp("written")
    url = f"s3://{s3.bucket()}/sweeps/p"
    config = {
        "name": "remote-p",
        "benchmark": "perception",
        "suite": str(write_suite(folder / "suite")),
        "agent": "oracle",
        "output": url,
        "storage": {"cache_dir": str(folder / "mirrors")},
    }
    (folder / "p.yaml").write_text(yaml.safe_dump(config))
    code, out = run_here(folder / "p.yaml", "--progress", "none")
    assert code == 0, out
    assert f"all results are in {url}" in out
    return url, folder / "mirrors" / "s3" / url.removeprefix("s3://")


def test_the_sweep_puts_its_whole_run_directory_in_the_bucket(written: tuple[str, Path], s3: S3Server) -> None:
    url, mirror = written
    location = parse_location(url)
    bucket, prefix = location.root.split("/", 1)
    keys = [key.removeprefix(prefix + "/") for key in s3.keys(bucket, prefix)]
    for name in ("manifest.json", "report.md", "events.jsonl", "lease.json", "jobs/part-000001.parquet"):
        assert name in keys
    assert {"steps/part-000001.parquet", "tests/part-000001.parquet", "perception/part-000001.parquet"} <= set(keys)
    assert not [key for key in keys if key.startswith("journal/")]  # compacted: the entries are gone
    local = {str(p.relative_to(mirror)) for p in mirror.rglob("*") if p.is_file() and not p.name.startswith(".")}
    assert local <= set(keys)  # everything the driver wrote is in the bucket
    assert sum(key.startswith("images/") for key in keys) == 3  # the perception screenshots, once each
    assert sum(key.endswith("trajectory.jsonl") for key in keys) == 8
    assert b'"released":true' in s3.read(bucket, f"{prefix}/lease.json")
    assert s3.read(bucket, f"{prefix}/manifest.json") == (mirror / "manifest.json").read_bytes()
    secret = CREDENTIALS["AWS_SECRET_ACCESS_KEY"].encode()  # in the driver's environment, never in the run
    assert not [key for key in s3.keys(bucket, prefix) if secret in s3.read(bucket, key)]
    assert not [p for p in mirror.rglob("*") if p.is_file() and secret in p.read_bytes()]


def test_status_and_report_read_the_bucket(written: tuple[str, Path]) -> None:
    url, _ = written
    status = invoke("status", url)
    assert status.returncode == 0, status.stderr
    assert "8/8 decided: passed 8, failed 0" in status.stdout and url in status.stdout
    report = invoke("report", url, "--format", "md")
    assert report.returncode == 0, report.stderr
    assert "| oracle | 8 |" in report.stdout


def test_load_results_reads_the_shards_in_the_bucket_without_downloading_the_run(written: tuple[str, Path]) -> None:
    url, mirror = written
    table = load_results(url)
    assert table.num_rows == 8 and set(table.column("outcome").to_pylist()) == {"passed"}
    assert load_results(url, "perception").num_rows == 8
    view = open_view(url)
    assert not list(view.rglob("*.parquet")) and not (view / "artifacts").exists()  # shards stay in the bucket
    assert sorted(RunStore(view).attempts()) == sorted(RunStore(mirror).attempts())


def test_view_exports_and_serves_a_remote_run(written: tuple[str, Path], tmp_path: Path, s3: S3Server) -> None:
    url, _ = written
    location = parse_location(url)
    bucket, prefix = location.root.split("/", 1)
    image = next(key for key in s3.keys(bucket, prefix) if "/images/" in key).rsplit("/", 1)[1]
    done = invoke("view", url, "--export", str(tmp_path / "site"))
    assert done.returncode == 0, done.stderr
    assert (tmp_path / "site" / "index.html").is_file()
    assert len(list((tmp_path / "site").rglob("images/*.png"))) == 3  # fetched from the bucket for the export
    server = subprocess.Popen([SCRATCHWORLD, "view", url, "--port", "0"], stdout=subprocess.PIPE, text=True, cwd=REPO)
    try:
        assert server.stdout is not None
        line = server.stdout.readline()
        address = re.search(r"http://127\.0\.0\.1:\d+/", line)
        assert address is not None, line
        with urllib.request.urlopen(address.group(0) + "runs/0/index.html") as page:
            assert "remote-p" in page.read().decode()
        with urllib.request.urlopen(address.group(0) + f"runs/0/images/{image}") as served:  # fetched on request
            assert served.read() == s3.read(bucket, f"{prefix}/images/{image}")
    finally:
        server.kill()
        server.communicate()


def test_compare_takes_a_remote_run_on_either_side(written: tuple[str, Path]) -> None:
    url, mirror = written
    done = invoke("compare", f"{url}:oracle", f"{mirror}:oracle", "--format", "json")
    assert done.returncode == 0, done.stderr
    assert '"jobs": 8' in done.stdout


@pytest.fixture(scope="module")
def task_run(tmp_path_factory: pytest.TempPathFactory, s3: S3Server) -> str:
    """A hand-made task-episode run (three jobs with trajectories and final projects) put in the bucket."""
    folder = tmp_path_factory.mktemp("tasks") / "run"
    records = [record(n) for n in range(3)]
    harness = HarnessFingerprint(digest="f1ngerpr1nt00000", parts={})
    make_run(folder, records, planned=3, tasks=3, suite_hash="suitehash", harness=harness, name="unit")
    store = RunStore(folder)
    for rec in records:
        worker_steps = episode(spec(int(rec.job.job_id.removeprefix("job"))), 1, "passed").steps
        steps = "".join(step.model_dump_json() + "\n" for step in worker_steps)
        store.write_artifact(rec.job.job_id, 1, "trajectory.jsonl", steps.encode())
        store.write_artifact(rec.job.job_id, 1, "final.sb3", f"project of {rec.job.job_id}".encode())
    url = f"s3://{s3.bucket()}/hand/run"
    fs = parse_location(url).filesystem()
    for path in folder.rglob("*"):
        if path.is_file() and not path.name.startswith("."):
            fs.pipe_file(f"{url.removeprefix('s3://')}/{path.relative_to(folder)}", path.read_bytes())
    return url


def test_export_reads_a_remote_runs_rows_and_trajectories(task_run: str, tmp_path: Path) -> None:
    done = invoke("export", task_run, "--format", "atif", "--out", str(tmp_path / "atif"))
    assert done.returncode == 0, done.stderr
    trajectories = sorted((tmp_path / "atif").rglob("*.json"))
    assert len(trajectories) == 3
    assert "load_project" in trajectories[0].read_text()  # the steps of the trajectory artifact fetched
    board = invoke("export", task_run, "--format", "leaderboard", "--out", str(tmp_path / "board"))
    assert board.returncode == 0, board.stderr


def test_regrade_reads_a_remote_sources_final_projects(task_run: str) -> None:
    source = read_source(open_view(task_run))
    assert len(source.jobs) == 3 and not source.without_project
    for job in source.jobs:
        assert (job.artifacts / "final.sb3").read_bytes() == f"project of {job.row.job_id}".encode()
