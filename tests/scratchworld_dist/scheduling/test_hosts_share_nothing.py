"""docs/cluster.md's recipe on hosts that share nothing, and a partition of one of them.

Three hosts made by the test (``tests/support/netns_hosts.py``): each its own network namespace and
address in 10.201.0.0/24, its own /tmp, /dev/shm and home, its own processes and hostname; the checkout
is shared read-only, as an install on every machine would be. host-0 holds the head (no browsers), the
driver, whose config and suite are on host-0's own /tmp, and an S3 server (moto's, on host-0's loopback) that
takes the run directory; host-1 and host-2 hold one editor each. A sweep of real browser episodes runs across
both; once host-2 has delivered a verdict and holds another job, its link is taken down. Its job is sent to
host-1 and decided there, the run's log and events name the lost node, and every job is decided exactly
once: in the bucket, read back whole onto host-0's disk after the driver's mirror is gone.
"""

from __future__ import annotations

import shutil
import subprocess
import sys
import time
from collections import Counter
from collections.abc import Callable, Iterator
from pathlib import Path

import pytest
import yaml
from pydantic import ValidationError

from scratchworld_dist.results import JobStart, NodeLost, RunStore, read_events, read_manifest
from tests.conftest import REPO
from tests.support.netns_cluster import HostCluster
from tests.support.netns_hosts import Host, IsolatedHosts, unavailable
from tests.support.s3_server import CREDENTIALS, MOTO_SERVER

pytestmark = [pytest.mark.ray, pytest.mark.browser, pytest.mark.slow]

TASKS = [
    "sum_two_numbers", "quiz_score", "bouncing_ball_stuck", "power_of_number", "click_counter_reset",
    "double_each_letter",
]  # fmt: skip

MIRRORS = "/tmp/mirrors"
"""The driver's local mirror of the remote run (``storage.cache_dir``), on host-0's own disk."""

S3_PORT = 9000
S3_ENV = {**CREDENTIALS, "AWS_ENDPOINT_URL": f"http://127.0.0.1:{S3_PORT}"}
"""How host-0's processes reach its S3 server (its loopback: nothing outside host-0 can)."""

_ON_HOST_0 = """
import sys, time, boto3, botocore.exceptions, fsspec
bucket, target = sys.argv[1], sys.argv[2]
client = boto3.client("s3")
for _ in range(600):  # the server is starting
    try:
        client.list_buckets()
        break
    except botocore.exceptions.EndpointConnectionError:
        time.sleep(0.1)
if target == "-":
    client.create_bucket(Bucket=bucket)
else:
    fsspec.filesystem("s3").get(f"{bucket}/apart/", target, recursive=True)
"""
"""Run on host-0: make the bucket (target ``-``) or copy the run out of it onto host-0's disk."""


def from_bucket(driver_host: Host, target: str) -> None:
    done = driver_host.run([sys.executable, "-c", _ON_HOST_0, "runs", target], env=S3_ENV)
    assert done.returncode == 0, done.stderr


@pytest.fixture
def hosts() -> Iterator[IsolatedHosts]:
    reason = unavailable()
    if reason is not None:
        pytest.skip(reason)
    made = IsolatedHosts(3)
    try:
        yield made
    finally:
        made.close()
        listed = subprocess.run(["ip", "netns", "list"], capture_output=True, text=True).stdout
        assert made.tag not in listed, "a namespace outlived the test"
        assert not [host.pid for host in made.hosts if Path(f"/proc/{host.pid}").exists()], "a host outlived it"


@pytest.fixture
def s3(hosts: IsolatedHosts, tmp_path: Path) -> Iterator[subprocess.Popen[bytes]]:
    """moto's S3 server on host-0's loopback."""
    with (tmp_path / "moto.log").open("wb") as log:
        server = subprocess.Popen(
            hosts.hosts[0].command([MOTO_SERVER, "-H", "127.0.0.1", "-p", str(S3_PORT)]), stdout=log, stderr=log
        )
    try:
        yield server
    finally:
        server.kill()
        server.wait()


def wait_until(condition: Callable[[], bool], driver: subprocess.Popen[bytes], log: Path, timeout_s: float) -> None:
    """Until ``condition`` holds; fails if the driver exits first or on a hang (a generous deadline)."""
    deadline = time.monotonic() + timeout_s
    while not condition():
        assert driver.poll() is None, f"the driver ended before the condition held:\n{log.read_text()}"
        assert time.monotonic() < deadline, f"no progress in {timeout_s:g} s:\n{log.read_text()}"
        time.sleep(0.2)


def holds_second_job(driver_host: Host, hostname: str) -> bool:
    """``hostname`` committed a verdict and its worker holds another job (started, not committed)."""
    mirrors = list(driver_host.path(MIRRORS).glob("s3/*/apart"))
    if not mirrors or not (mirrors[0] / "journal").exists():
        return False
    folder = mirrors[0]
    mine = [row for row in RunStore(folder).job_rows() if row.worker_host == hostname]
    if not mine:
        return False
    try:
        events = read_events(folder)
    except ValidationError:  # read while the driver was writing a line: look again
        return False
    sent = [e for e in events if isinstance(e, JobStart) and e.worker == mine[0].worker_index]
    return len(sent) > len(mine)


@pytest.mark.timeout(900)
def test_a_sweep_across_hosts_that_share_nothing_survives_a_partition(
    tmp_path: Path, hosts: IsolatedHosts, s3: subprocess.Popen[bytes]
) -> None:
    driver_host, first, second = hosts.hosts
    cluster = HostCluster(driver_host)
    cluster.head()
    cluster.node(first, browsers=1)
    cluster.node(second, browsers=1)
    cluster.wait_for(nodes=3, browsers=2)

    shutil.copytree(REPO / "tasks", driver_host.path("/tmp/suite"))  # the suite is on the driver's disk only
    from_bucket(driver_host, "-")
    config = {
        "name": "apart",
        "suite": "/tmp/suite",
        "agent": "oracle",
        "tasks": {"ids": TASKS},
        "output": "s3://runs/apart",
        "storage": {"cache_dir": MIRRORS},
        "ray": {"address": cluster.address, "connect_timeout_s": 60},
        "limits": {"pages_per_worker": 1, "episode_timeout_s": 300, "retries": 2},
    }
    driver_host.path("/tmp/apart.yaml").write_text(yaml.safe_dump(config))
    for host in (first, second):
        assert not host.path("/tmp/suite").exists()

    log = tmp_path / "driver.log"
    driver = cluster.driver("/tmp/apart.yaml", log, env=S3_ENV)
    try:
        wait_until(lambda: holds_second_job(driver_host, second.name), driver, log, timeout_s=600)
        hosts.cut(second)
        code = driver.wait(timeout=600)
    finally:
        if driver.poll() is None:
            driver.kill()
    out = log.read_text()
    assert code == 0, out
    assert s3.poll() is None, "the S3 server ended during the run"
    assert CREDENTIALS["AWS_SECRET_ACCESS_KEY"] not in out

    # The run as the bucket holds it, copied onto host-0's disk with the driver's mirror gone.
    shutil.rmtree(driver_host.path(MIRRORS))
    from_bucket(driver_host, "/tmp/fetched")
    folder = driver_host.path("/tmp/fetched")
    for host in (first, second):  # nothing of the run reached a worker's disk
        assert not host.path(MIRRORS).exists() and not host.path("/tmp/fetched").exists()

    rows = RunStore(folder).job_rows()
    verdicts = Counter(row.task_id for row in rows if row.outcome != "error")
    assert verdicts == Counter(TASKS), out  # every job decided, none twice
    assert {row.outcome for row in rows if row.outcome != "error"} == {"passed"}
    assert {row.worker_host for row in rows if row.outcome == "passed"} == {first.name, second.name}

    # host-2's job in flight: lost with its node, then decided on host-1, its project back on the driver's disk.
    (lost,) = [row for row in rows if row.outcome == "error"]
    assert lost.error_class == "worker_died", lost.error_message
    assert f"node {second.name} ({second.address}, node " in (lost.error_message or ""), lost.error_message
    (again,) = [row for row in rows if row.job_id == lost.job_id and row.outcome != "error"]
    assert again.attempt > lost.attempt and again.worker_host == first.name
    assert again.artifact_dir is not None and (folder / again.artifact_dir / "final.sb3").is_file()

    (node_lost,) = [event for event in read_events(folder) if isinstance(event, NodeLost)]
    assert (node_lost.hostname, node_lost.address) == (second.name, second.address)
    assert node_lost.workers == [next(row.worker_index for row in rows if row.worker_host == second.name)]
    said = [line for line in out.splitlines() if line.startswith("node lost: ")]
    assert said == [
        f"node lost: {second.name} ({second.address}, node {node_lost.node_id[:8]}) left the cluster "
        f"({node_lost.reason}); it held worker(s) {', '.join(map(str, node_lost.workers))}: "
        "their jobs in flight end as worker_died"
    ], out

    manifest = read_manifest(folder)
    assert manifest is not None
    assert sorted(node.address for node in manifest.sessions[-1].nodes) == [first.address, second.address]
