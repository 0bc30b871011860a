"""The parts of a remote run directory against a real S3 API server (moto's, on 127.0.0.1): URLs and the
credentials refused in them, the lease and its expiry, the uploader through an outage, and a bucket that cannot
take a run."""

from __future__ import annotations

import json
import os
import time
from datetime import UTC, datetime
from pathlib import Path

import pytest
import yaml

from scratchworld_dist._errors import ConfigError, RunDirError
from scratchworld_dist.api import load_results
from scratchworld_dist.results.remote._lease import Lease
from scratchworld_dist.results.remote._location import parse_location, redact
from scratchworld_dist.results.remote._sync import RemoteRun
from scratchworld_dist.results.remote._uploader import Uploader
from scratchworld_dist.results.remote._view import open_view
from scratchworld_dist.sweep import load_sweep_config
from tests.conftest import REPO
from tests.support.cli_runner import invoke
from tests.support.run_dirs import job, make_run
from tests.support.s3_server import S3Server

SECRET = "wJalrXUtnFEMIbPxRfiCYSECRETKEY"


def wait_for(condition: object, timeout: float, what: str) -> None:
    deadline = time.monotonic() + timeout
    while not condition():  # type: ignore[operator]
        if time.monotonic() > deadline:
            raise AssertionError(f"timed out waiting for {what}")
        time.sleep(0.05)


def test_a_url_with_credentials_is_refused_in_one_line_without_them(tmp_path: Path) -> None:
    with pytest.raises(RunDirError) as caught:
        parse_location(f"s3://AKIAEXAMPLE:{SECRET}@bucket/runs")
    message = str(caught.value)
    assert SECRET not in message and "AKIAEXAMPLE" not in message and "\n" not in message
    assert "s3://***@bucket/runs" in message and "AWS_ACCESS_KEY_ID" in message
    assert redact(f"gs://user:{SECRET}@b/p and more") == "gs://***@b/p and more"
    config = tmp_path / "sweep.yaml"
    fields = {"name": "t", "suite": str(REPO / "tasks"), "agent": "oracle", "output": f"s3://k:{SECRET}@b/run"}
    config.write_text(yaml.safe_dump(fields))
    with pytest.raises(ConfigError, match=r"output: .*credentials in a URL are refused") as refused:
        load_sweep_config(config)
    assert SECRET not in str(refused.value)


@pytest.mark.parametrize(
    ("text", "message"),
    [("s3://", "names no bucket"), ("s3://b/run?x=1", "no \\?query"), ("results/run", "not a URL")],
)
def test_bad_urls_are_one_line(text: str, message: str) -> None:
    with pytest.raises(RunDirError, match=message):
        parse_location(text)


def test_urls_name_their_objects() -> None:
    location = parse_location("s3://lab/sweeps/demo/")
    assert (location.url, location.key("jobs/part-000001.parquet")) == (
        "s3://lab/sweeps/demo",
        "lab/sweeps/demo/jobs/part-000001.parquet",
    )
    assert parse_location("file:///tmp/runs/a").root == "/tmp/runs/a"


def test_a_live_lease_keeps_a_second_driver_off_and_says_whose_it_is(s3: S3Server) -> None:
    location = parse_location(f"s3://{s3.bucket()}/run")
    first = Lease(location.filesystem(), location, ttl_s=60)
    assert first.acquire() is None
    second = Lease(location.filesystem(), location, ttl_s=60)
    with pytest.raises(RunDirError) as caught:
        second.acquire()
    message = str(caught.value)
    assert "another scratchworld run is writing here" in message
    assert f"pid {os.getpid()}" in message and first.record.host in message
    assert first.record.since.isoformat(timespec="seconds") in message
    first.release()
    before = second.acquire()  # a released lease is free at once, and says who wrote last
    assert before is not None and before.token == first.record.token and before.released
    second.release()


def test_a_lease_whose_holder_stopped_renewing_expires(s3: S3Server) -> None:
    location = parse_location(f"s3://{s3.bucket()}/run")
    stale = Lease(location.filesystem(), location, ttl_s=4)
    stale.acquire()
    stale.stop_renewing()  # as a driver on a machine that went away
    late = Lease(location.filesystem(), location, ttl_s=60)
    refusal = ""
    try:
        late.acquire()
    except RunDirError as refused:  # within its term the lease still holds (a loaded machine may be past it)
        refusal = str(refused)
    if not refusal:
        assert datetime.now(tz=UTC) >= stale.record.expires()
        late.release()
        return
    assert "another scratchworld run" in refusal
    took: list[bool] = []

    def taken() -> bool:
        try:
            late.acquire()
        except RunDirError:
            return False
        took.append(True)
        return True

    wait_for(taken, 30, "the stale lease to expire")
    record = json.loads(s3.read(location.root.split("/")[0], "run/lease.json"))
    assert record["token"] == late.record.token
    late.release()


def test_uploads_wait_through_an_outage_in_order_and_catch_up(s3: S3Server) -> None:
    bucket = s3.bucket()
    location = parse_location(f"s3://{bucket}/run")
    problems: list[str | None] = []
    uploader = Uploader(location.filesystem(), lambda reason, pending: problems.append(reason))
    uploader.put_bytes(location.key("journal/a.json"), b"1", committed_at=time.monotonic())
    assert uploader.drain(60)
    s3.relay.down()
    try:
        for n in range(5):
            uploader.put_bytes(location.key(f"journal/b{n}.json"), b"2", committed_at=time.monotonic())
        wait_for(lambda: uploader.problem is not None, 60, "the uploader to notice the outage")
        assert uploader.pending() == 5 and problems[0] is not None
        assert s3.keys(bucket) == ["run/journal/a.json"]
    finally:
        s3.relay.up()
    assert uploader.drain(120)
    assert s3.keys(bucket) == ["run/journal/a.json", *(f"run/journal/b{n}.json" for n in range(5))]
    assert problems[-1] is None and uploader.problem is None
    assert len(uploader.lags) == 6
    assert uploader.close(0) == 0


def test_a_bucket_that_does_not_exist_or_refuses_writes_is_one_line(s3: S3Server, tmp_path: Path) -> None:
    with pytest.raises(RunDirError) as missing:
        RemoteRun.open("s3://no-such-bucket-here/run", tmp_path / "a", 60, print)
    assert str(missing.value).startswith("s3://no-such-bucket-here/run: cannot write results here: the bucket does")
    bucket = s3.bucket()
    deny = {
        "Version": "2012-10-17",
        "Statement": [
            {"Effect": "Deny", "Principal": "*", "Action": "s3:PutObject", "Resource": f"arn:aws:s3:::{bucket}/*"}
        ],
    }
    s3.client().put_bucket_policy(Bucket=bucket, Policy=json.dumps(deny))
    with pytest.raises(RunDirError) as refused:
        RemoteRun.open(f"s3://{bucket}/run", tmp_path / "b", 60, print)
    assert f"s3://{bucket}/run: cannot write results here: the store refuses writes" in str(refused.value)
    for error in (missing.value, refused.value):
        assert "\n" not in str(error) and "testing-secret" not in str(error)


def test_run_on_a_missing_bucket_stops_in_one_line_before_any_editor_opens(s3: S3Server, tmp_path: Path) -> None:
    config = tmp_path / "sweep.yaml"
    fields = {
        "name": "t",
        "suite": str(REPO / "tasks"),
        "agent": "oracle",
        "output": "s3://no-such-bucket-here/sweeps/t",
        "storage": {"cache_dir": str(tmp_path / "mirrors")},
    }
    config.write_text(yaml.safe_dump(fields))
    done = invoke("run", str(config), "--progress", "none")
    assert done.returncode != 0
    lines = [line for line in (done.stdout + done.stderr).splitlines() if line.strip()]
    assert lines == [
        "error: s3://no-such-bucket-here/sweeps/t: cannot write results here: the bucket does not exist "
        "(The specified bucket does not exist)"
    ]
    assert not (tmp_path / "mirrors").exists()  # nothing written, no worker started


def test_a_driver_whose_lease_was_taken_stops_renewing_it_and_says_who_took_it(s3: S3Server) -> None:
    bucket = s3.bucket()
    location = parse_location(f"s3://{bucket}/run")
    holder = Lease(location.filesystem(), location, ttl_s=1.5)
    holder.acquire()
    taker = Lease(location.filesystem(), location, ttl_s=60)
    # As a driver that found the lease expired while the holder's store was unreachable. A renewal already
    # between its read and its write puts the holder's record back over it (the taker then loses the lease
    # at its own next renewal, so one driver still holds it); the taker writes again after such a renewal.
    for _ in range(5):
        taker._write()
        deadline = time.monotonic() + 10 * holder.record.ttl_s
        while holder.lost_to is None and time.monotonic() < deadline:
            if holder.read().token == holder.record.token:  # type: ignore[union-attr]
                break
            time.sleep(0.05)
        if holder.lost_to is not None:
            break
    assert holder.lost_to is not None, "the holder never noticed the taken lease at its renewals"
    assert f"pid {taker.record.pid}" in str(holder.lost_to)
    holder.release()  # a lost lease is not released: it is the taker's now
    assert json.loads(s3.read(bucket, "run/lease.json"))["token"] == taker.record.token


def test_any_fsspec_url_reads_in_place_here_a_file_url(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))
    run = make_run(tmp_path / "run", [job("a"), job("b", "failed")], planned=2, tasks=2)
    table = load_results(f"file://{run}")
    assert sorted(table.column("job_id").to_pylist()) == ["a", "b"]
    view = open_view(f"file://{run}")
    assert view.is_relative_to(tmp_path / "cache") and not list(view.rglob("*.parquet"))
    assert "2/2 decided: passed 1, failed 1" in invoke("status", f"file://{run}").stdout
