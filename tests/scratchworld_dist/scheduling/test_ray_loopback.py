"""No Ray process this project starts listens on anything but loopback: not a sweep's private Ray (even when the
environment turns Ray's cluster mode on), nor the `ray start` nodes that tests and benchmarks start.

Each check reads the listening sockets of every Ray process (psutil) after a task has run, so the worker
pool and the agents that start it are up, and first checks that it found the processes it should.
"""

from __future__ import annotations

import contextlib
import ipaddress
import json
import os
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time
from collections import Counter
from collections.abc import Callable, Iterable, Iterator, Mapping
from pathlib import Path

import psutil
import pytest

from tests.conftest import REPO
from tests.support.ray_loopback import RAY_START


def is_loopback(address: str) -> bool:
    """127.0.0.0/8 or ::1, also as an IPv4-mapped IPv6 address (a dual-stack socket bound to 127.0.0.1)."""
    ip = ipaddress.ip_address(address)
    mapped = getattr(ip, "ipv4_mapped", None)
    return ip.is_loopback or (mapped is not None and mapped.is_loopback)


def listening(processes: Iterable[psutil.Process]) -> dict[str, list[str]]:
    """Each process (``name pid``) with the addresses it listens on (TCP LISTEN or bound UDP)."""
    found: dict[str, list[str]] = {}
    for process in processes:
        with contextlib.suppress(psutil.NoSuchProcess):
            sockets = [
                f"{c.laddr.ip}:{c.laddr.port}"
                for c in process.net_connections(kind="inet")
                if c.status == psutil.CONN_LISTEN or (c.type == socket.SOCK_DGRAM and not c.raddr)
            ]
            found[f"{process.name()} {process.pid}"] = sockets
    return found


def exposed(found: dict[str, list[str]]) -> list[str]:
    return [
        f"{name} on {addr}"
        for name, addrs in found.items()
        for addr in addrs
        if not is_loopback(addr[: addr.rindex(":")])
    ]


def names_listening(found: dict[str, list[str]]) -> Counter[str]:
    """How many processes of each name listen."""
    return Counter(name.rsplit(" ", 1)[0] for name, addrs in found.items() if addrs)


def settled(
    processes: Callable[[], list[psutil.Process]], expected: Mapping[str, int], timeout_s: float = 120.0
) -> tuple[dict[str, list[str]], list[str]]:
    """The listeners once ``expected`` processes of each name listen (Ray's agents start after its nodes do),
    and every non-loopback address seen while waiting. Fails if they do not all listen in time."""
    deadline = time.monotonic() + timeout_s
    seen: list[str] = []
    while True:
        found = listening(processes())
        seen += [address for address in exposed(found) if address not in seen]
        have = names_listening(found)
        if all(have[name] >= count for name, count in expected.items()):
            return found, seen
        assert time.monotonic() < deadline, f"not all of {dict(expected)} listen after {timeout_s:g} s: {found}"
        time.sleep(0.2)


def ray_tree() -> list[psutil.Process]:
    """This process (a driver) and every process below it (the private Ray it started)."""
    driver = psutil.Process()
    return [driver, *driver.children(recursive=True)]


PRIVATE_RAY = {"gcs_server": 1, "raylet": 1, "ray::RuntimeEnvAgent": 1}


# -- a sweep's private Ray ------------------------------------------------------------------------------------


def test_no_process_of_a_sweeps_private_ray_listens_beyond_loopback(shared_ray: int) -> None:
    import ray

    @ray.remote
    def pid() -> int:
        return os.getpid()

    worker = ray.get(pid.remote())
    found, seen = settled(ray_tree, PRIVATE_RAY)
    driver = psutil.Process()
    assert found[f"{driver.name()} {driver.pid}"], found  # the driver's core worker listens too
    assert any(name.endswith(f" {worker}") and addresses for name, addresses in found.items()), found
    assert ray.util.get_node_ip_address() == "127.0.0.1"
    assert seen == []


PRIVATE_RAY_REPORT = """
import json, os, ray
from scratchworld_dist.scheduling import ray_runtime
from tests.scratchworld_dist.scheduling.test_ray_loopback import PRIVATE_RAY, names_listening, ray_tree, settled

@ray.remote
def pid():
    return os.getpid()

with ray_runtime(None, 1):
    ray.get(pid.remote())
    found, seen = settled(ray_tree, PRIVATE_RAY)
    node = ray.util.get_node_ip_address()
    print(json.dumps({"node": node, "names": sorted(names_listening(found)), "exposed": seen}))
"""


@pytest.mark.ray
def test_a_private_ray_stays_on_loopback_when_the_environment_turns_ray_cluster_mode_on() -> None:
    """With RAY_ENABLE_WINDOWS_OR_OSX_CLUSTER=1 (Ray's own default on Linux), Ray would swap 127.0.0.1 for this
    machine's address and bind its servers to every interface."""
    env = {**os.environ, "RAY_ENABLE_WINDOWS_OR_OSX_CLUSTER": "1", "PYTHONPATH": str(REPO)}
    env.pop("RAY_ADDRESS", None)
    done = subprocess.run(
        [sys.executable, "-c", PRIVATE_RAY_REPORT], env=env, cwd=REPO, capture_output=True, text=True, timeout=300
    )
    assert done.returncode == 0, done.stderr
    report = json.loads(done.stdout.strip().splitlines()[-1])
    assert report["node"] == "127.0.0.1"
    assert {"gcs_server", "raylet", "ray::RuntimeEnvAgent"} <= set(report["names"])
    assert report["exposed"] == []


# -- `ray start` nodes ----------------------------------------------------------------------------------------


class StartedNodes:
    """`ray start` nodes as the tests' ``Cluster`` (tests/support/ray_cluster.py) starts them, found and killed
    by a marker in their environment, so no one else's Ray is touched."""

    def __init__(self) -> None:
        self.temp_dir = Path(tempfile.mkdtemp(prefix="sw-lo-", dir="/tmp"))  # Ray's socket paths must be short
        self.marker = f"SCRATCHWORLD_TEST_LOOPBACK={self.temp_dir}".encode()
        with socket.socket() as probe:
            probe.bind(("127.0.0.1", 0))
            self.address = f"127.0.0.1:{probe.getsockname()[1]}"
        self.env = {**os.environ, "RAY_AUTH_MODE": "disabled", "SCRATCHWORLD_TEST_LOOPBACK": str(self.temp_dir)}
        for name in ("RAY_ADDRESS", "RAY_ENABLE_WINDOWS_OR_OSX_CLUSTER"):
            self.env.pop(name, None)

    def start(self, *args: str) -> None:
        command = [*RAY_START, *args, "--num-cpus", "1", "--disable-usage-stats", "--temp-dir", str(self.temp_dir)]
        done = subprocess.run(command, env=self.env, capture_output=True, text=True, timeout=180)
        assert done.returncode == 0, done.stdout + done.stderr

    def processes(self) -> list[psutil.Process]:
        """The processes that hold the marker (the nodes' services) and every process below them: Ray renames
        its agents and workers, which may overwrite the environment /proc shows."""
        found: dict[int, psutil.Process] = {}
        for process in psutil.process_iter():
            with contextlib.suppress(psutil.Error, OSError):
                if self.marker in Path(f"/proc/{process.pid}/environ").read_bytes().split(b"\0"):
                    found[process.pid] = process
                    found.update((child.pid, child) for child in process.children(recursive=True))
        return list(found.values())

    def stop(self) -> None:
        for process in self.processes():
            with contextlib.suppress(OSError):
                os.kill(process.pid, signal.SIGKILL)
        shutil.rmtree(self.temp_dir, ignore_errors=True)


@pytest.fixture
def nodes() -> Iterator[StartedNodes]:
    started = StartedNodes()
    try:
        yield started
    finally:
        started.stop()


RUN_ON_EACH_NODE = """
import json, sys, ray
ray.init(address=sys.argv[1], log_to_driver=False, configure_logging=False)
nodes = [n["NodeID"] for n in ray.nodes() if n["Alive"]]
strategy = ray.util.scheduling_strategies.NodeAffinitySchedulingStrategy
ips = ray.get([ray.remote(ray.util.get_node_ip_address).options(scheduling_strategy=strategy(n, soft=False)).remote()
               for n in nodes])
print(json.dumps({"nodes": len(nodes), "addresses": sorted(set(ips))}))
"""


@pytest.mark.ray
@pytest.mark.slow
def test_no_process_of_the_ray_start_nodes_of_tests_listens_beyond_loopback(nodes: StartedNodes) -> None:
    port = nodes.address.rsplit(":", 1)[1]
    nodes.start("--head", "--port", port, "--include-dashboard=false", "--resources", '{"browser": 0}')
    nodes.start("--address", nodes.address, "--resources", '{"browser": 1}')
    # A driver joins as the project's drivers do (cluster mode off) and runs a task on each node.
    driver_env = {**nodes.env, "RAY_ENABLE_WINDOWS_OR_OSX_CLUSTER": "0"}
    done = subprocess.run(
        [sys.executable, "-c", RUN_ON_EACH_NODE, nodes.address],
        env=driver_env,
        capture_output=True,
        text=True,
        timeout=180,
    )
    assert done.returncode == 0, done.stderr
    assert json.loads(done.stdout.strip().splitlines()[-1]) == {"nodes": 2, "addresses": ["127.0.0.1"]}
    found, seen = settled(nodes.processes, {"gcs_server": 1, "raylet": 2, "ray::RuntimeEnvAgent": 2})
    assert seen == [], found
