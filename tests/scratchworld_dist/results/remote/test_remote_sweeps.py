"""Sweeps writing to a real S3 API server (moto's, on 127.0.0.1) that fails them: the driver killed with SIGKILL
while uploads are in flight and resumed from an empty local folder on the same bucket, and the store gone mid-run
and back. Synthetic (browserless) episodes pace the jobs; each driver is ``scratchworld run`` in a subprocess."""

from __future__ import annotations

import os
import signal
import time
from collections import Counter
from pathlib import Path
from typing import Any

import pytest
import yaml

from scratchworld_dist.api import load_results
from scratchworld_dist.results.remote._location import parse_location
from tests.conftest import REPO
from tests.support.s3_server import S3Server
from tests.support.sweep_driver import Driver, run

pytestmark = [pytest.mark.ray, pytest.mark.slow]

JOBS = 60  # 12 tasks x 5 seeds


def write_config(folder: Path, url: str, mirrors: str, file: str = "sweep", **storage: Any) -> Path:
    config = {
        "name": "remote",
        "suite": str(REPO / "tasks"),
        "agent": "oracle",
        "seeds": 5,
        "episodes": {"synthetic": {"duration_s": 0.3}},
        "output": url,
        "storage": {"cache_dir": str(folder / mirrors), **storage},
    }
    path = folder / f"{file}-{mirrors}.yaml"
    path.write_text(yaml.safe_dump(config))
    return path


def wait_for(condition: object, timeout: float, what: str) -> None:
    deadline = time.monotonic() + timeout
    while not condition():  # type: ignore[operator]
        if time.monotonic() > deadline:
            raise AssertionError(f"timed out waiting for {what}")
        time.sleep(0.1)


def entries(s3: S3Server, url: str) -> int:
    """Journal entries in the bucket (each a committed attempt of a segment not yet compacted)."""
    bucket, prefix = parse_location(url).root.split("/", 1)
    return sum("/journal/" in key for key in s3.keys(bucket, prefix))


def committed_lines(mirror: Path) -> int:
    journal = mirror / "journal"
    return sum(len(p.read_bytes().splitlines()) for p in journal.glob("*.jsonl")) if journal.exists() else 0


def mirror_of(folder: Path, mirrors: str, url: str) -> Path:
    return folder / mirrors / "s3" / url.removeprefix("s3://")


def test_a_driver_killed_mid_upload_resumes_from_an_empty_folder_losing_and_doubling_nothing(
    tmp_path: Path, s3: S3Server, drivers: list[Driver]
) -> None:
    url = f"s3://{s3.bucket()}/sweeps/killed"
    first = Driver(write_config(tmp_path, url, "machine-a"))
    drivers.append(first)
    wait_for(lambda: entries(s3, url) >= 3, 180, "the first journal entries in the bucket")
    s3.relay.down()  # uploads now hang in flight
    try:
        mirror = mirror_of(tmp_path, "machine-a", url)
        wait_for(lambda: committed_lines(mirror) >= entries(s3, url) + 3, 120, "commits the bucket has not seen")
        os.kill(first.process.pid, signal.SIGKILL)  # the driver only; its Ray helpers are reaped after the test
        first.process.wait()
    finally:
        s3.relay.up()
    before = {(row["job_id"], row["attempt"]) for row in load_results(url, effective=False).to_pylist()}
    assert 3 <= len(before) < JOBS

    # Another machine: an empty local folder, the same bucket; the killed driver's lease is taken over.
    code, out = run(drivers, write_config(tmp_path, url, "machine-b"))
    assert code == 0, out
    assert f"{len(before)} already decided" in " ".join(out.split())
    assert "rebuilt from the bucket" in out and f"all results are in {url}" in out

    rows = load_results(url, effective=False).to_pylist()
    decided = Counter(row["job_id"] for row in rows if row["outcome"] != "error")
    assert len(decided) == JOBS and set(decided.values()) == {1}  # every job decided, none twice
    assert before <= {(row["job_id"], row["attempt"]) for row in rows}  # nothing the bucket had is lost
    assert entries(s3, url) == 0  # all compacted into shards


def test_a_store_gone_mid_run_leaves_the_sweep_running_and_the_uploads_catch_up(
    tmp_path: Path, s3: S3Server, drivers: list[Driver]
) -> None:
    url = f"s3://{s3.bucket()}/sweeps/outage"
    config = write_config(tmp_path, url, "here", drain_timeout_s=0)
    driver = Driver(config)
    drivers.append(driver)
    wait_for(lambda: entries(s3, url) >= 2, 180, "the first journal entries in the bucket")
    s3.relay.down()
    try:
        code, out = driver.wait()
    finally:
        s3.relay.up()
    assert code == 0, out  # every job ran while the store was away
    assert f"uploads to {url} are failing" in out
    pending = [line for line in out.splitlines() if line.startswith("uploads: ")]
    assert len(pending) == 1 and f"not yet in {url}" in pending[0] and "pushed by the next run" in pending[0]
    assert f"ran {JOBS} attempt(s): passed {JOBS}" in " ".join(out.split())

    # The store is back: the same machine's next run (waiting for its uploads this time) pushes what is pending.
    code, out = run(drivers, write_config(tmp_path, url, "here", file="again"))
    assert code == 0, out
    assert "file(s) the bucket lacked pushed from it" in out and f"all results are in {url}" in out
    assert f"{JOBS} already decided, 0 to run" in " ".join(out.split())
    rows = load_results(url, effective=False).to_pylist()
    assert len(rows) == JOBS and len({row["job_id"] for row in rows}) == JOBS
    assert entries(s3, url) == 0
