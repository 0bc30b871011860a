"""A local two-node Ray cluster of real ``ray start`` processes, owned and cleaned up by the benchmark alone.

Other people's Ray and Chromium may run on the same host, so nothing here looks processes up by
name host-wide (no ``ray stop``, no ``pkill``): each node is a ``ray start --block`` in its own
session, so its Ray services share one process group, and every process below those nodes (worker
actors, their Playwright drivers, Chromium) is found by walking ``/proc`` from them. Processes
seen that way are remembered by (pid, start time) while the run lasts, so one that was orphaned
(a killed worker's Chromium) is still found, and never confused with a new process reusing its pid.
"""

from __future__ import annotations

import contextlib
import json
import os
import signal
import socket
import subprocess
import sys
import time
from dataclasses import dataclass
from pathlib import Path

from tests.support.ray_loopback import RAY_START

STOP_GRACE_S = 45.0
"""A node drains for up to 30 s after SIGTERM; past this it is killed."""


@dataclass(frozen=True)
class Proc:
    """One process as ``/proc`` shows it."""

    pid: int
    ppid: int
    start: int
    """Start time in clock ticks after boot: with the pid, a process's identity."""

    cmdline: str


def process_table() -> dict[int, Proc]:
    """Every process of the host (those that vanish while being read are skipped)."""
    table: dict[int, Proc] = {}
    for entry in os.scandir("/proc"):
        if not entry.name.isdigit():
            continue
        try:
            stat = Path(entry.path, "stat").read_text()
            raw = Path(entry.path, "cmdline").read_bytes()
        except OSError:
            continue
        fields = stat[stat.rindex(")") + 2 :].split()  # the command name may hold spaces and parentheses
        pid = int(entry.name)
        table[pid] = Proc(pid, int(fields[1]), int(fields[19]), raw.replace(b"\0", b" ").decode(errors="replace"))
    return table


def descendants(table: dict[int, Proc], roots: set[int]) -> list[Proc]:
    children: dict[int, list[Proc]] = {}
    for proc in table.values():
        children.setdefault(proc.ppid, []).append(proc)
    found: list[Proc] = []
    stack = list(roots)
    while stack:
        for child in children.get(stack.pop(), []):
            found.append(child)
            stack.append(child.pid)
    return found


def _accepts(host: str, port: int) -> bool:
    try:
        socket.create_connection((host, port), timeout=1).close()
    except OSError:
        return False
    return True


def free_port() -> int:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return int(probe.getsockname()[1])


class LocalCluster:
    """A head node and one more node on this host, each offering ``browser`` slots."""

    def __init__(self, workdir: Path, slots: list[int], env: dict[str, str], object_store_mb: int = 256) -> None:
        """``env`` is added to the nodes' environment; their worker processes inherit it."""
        self.workdir = workdir
        self.slots = slots
        self.env = {**os.environ, **env}
        self.env.pop("RAY_ENABLE_WINDOWS_OR_OSX_CLUSTER", None)  # set by scratchworld_dist: it forbids a second node
        self.object_store_mb = object_store_mb
        self.address = ""
        self.nodes: list[subprocess.Popen[bytes]] = []
        self._seen: dict[tuple[int, int], str] = {}

    def start(self, timeout_s: float = 120.0) -> str:
        """Start the nodes and wait until the cluster shows all of them; returns the address."""
        self.workdir.mkdir(parents=True, exist_ok=True)
        temp_dir = self.workdir / "ray"
        port = free_port()
        self.address = f"127.0.0.1:{port}"
        for index, slots in enumerate(self.slots):
            args = [
                *RAY_START,  # on 127.0.0.1 only
                "--block",
                "--num-cpus=1",
                "--disable-usage-stats",
                f"--resources={json.dumps({'browser': slots})}",
                f"--object-store-memory={self.object_store_mb * 2**20}",
                f"--temp-dir={temp_dir}",
                f"--dashboard-agent-listen-port={free_port()}",
                f"--metrics-export-port={free_port()}",
                f"--runtime-env-agent-port={free_port()}",
            ]
            if index == 0:
                args += [
                    "--head",
                    f"--port={port}",
                    "--include-dashboard=false",
                    f"--dashboard-port={free_port()}",
                ]
            else:
                args.append(f"--address={self.address}")
            with (self.workdir / f"node-{index}.log").open("wb") as log:
                self.nodes.append(
                    subprocess.Popen(args, stdout=log, stderr=subprocess.STDOUT, env=self.env, start_new_session=True)
                )
            self._wait_for(index + 1, sum(self.slots[: index + 1]), timeout_s)
        return self.address

    def _wait_for(self, nodes: int, slots: int, timeout_s: float) -> None:
        """Block until the cluster has ``nodes`` live nodes offering ``slots`` browser slots in all."""
        deadline = time.monotonic() + timeout_s
        host, port = self.address.split(":")
        while not _accepts(host, int(port)):  # Ray's own connect retries for minutes on a dead head
            self._check_alive()
            if time.monotonic() > deadline:
                raise RuntimeError(f"the head node does not listen on {self.address}; see {self.workdir}/node-*.log")
            time.sleep(0.5)
        probe = (
            "import ray, sys, time\n"
            "ray.init(address=sys.argv[1], log_to_driver=False, configure_logging=False)\n"
            "end = time.monotonic() + float(sys.argv[4])\n"
            "while time.monotonic() < end:\n"
            "    alive = sum(n['Alive'] for n in ray.nodes())\n"
            "    if alive >= int(sys.argv[2]) and ray.cluster_resources().get('browser', 0) >= int(sys.argv[3]):\n"
            "        sys.exit(0)\n"
            "    time.sleep(0.2)\n"
            "sys.exit(1)\n"
        )
        left = max(deadline - time.monotonic(), 1.0)
        args = [sys.executable, "-c", probe, self.address, str(nodes), str(slots), str(left)]
        # Cluster mode off: a probe in it would look for the head at this machine's network address, not 127.0.0.1.
        env = {**self.env, "RAY_ENABLE_WINDOWS_OR_OSX_CLUSTER": "0"}
        waiting = subprocess.Popen(args, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        try:
            while waiting.poll() is None:
                self._check_alive()
                time.sleep(0.5)
        finally:
            waiting.kill()
            waiting.wait()
        if waiting.returncode != 0:
            raise RuntimeError(f"the cluster at {self.address} did not show {nodes} node(s) in {timeout_s:g} s")

    def _check_alive(self) -> None:
        for node in self.nodes:
            if node.poll() is not None:
                raise RuntimeError(f"a ray node exited with {node.returncode}; see {self.workdir}/node-*.log")

    # -- the processes below the nodes ---------------------------------------------------------------

    def processes(self) -> list[Proc]:
        """Live processes below the nodes (Ray services, worker actors, Chromium), remembered for ``stop``."""
        found = descendants(process_table(), {node.pid for node in self.nodes})
        for proc in found:
            self._seen[(proc.pid, proc.start)] = proc.cmdline
        return found

    def worker_actors(self) -> list[Proc]:
        """The ``JobWorker`` actor processes."""
        return [p for p in self.processes() if p.cmdline.startswith("ray::JobWorker")]

    def chromium(self, kind: str) -> list[Proc]:
        """Chromium processes of the workers: ``browser`` (no ``--type``) or ``renderer`` (of a page)."""
        table = process_table()
        below = descendants(table, {p.pid for p in self.worker_actors()})
        found = []
        for proc in below:
            if Path(proc.cmdline.split(" ", 1)[0]).name != "chromium":  # not the crashpad handler
                continue
            page = "--top-chrome-webui" not in proc.cmdline and "--extension-process" not in proc.cmdline
            kind_of = "renderer" if "--type=renderer" in proc.cmdline and page else None
            if kind_of is None and "--type=" not in proc.cmdline:
                kind_of = "browser"
            if kind_of == kind:
                found.append(proc)
        return found

    # -- shutting down ---------------------------------------------------------------------------------

    def stop(self) -> list[str]:
        """Stop both nodes, then kill whatever of theirs outlived them; returns what had to be killed."""
        self.processes()
        for node in reversed(self.nodes):
            with contextlib.suppress(ProcessLookupError):
                os.killpg(node.pid, signal.SIGTERM)
        deadline = time.monotonic() + STOP_GRACE_S
        for node in self.nodes:
            with contextlib.suppress(subprocess.TimeoutExpired):
                node.wait(max(deadline - time.monotonic(), 0.1))
        for node in self.nodes:
            with contextlib.suppress(ProcessLookupError):
                os.killpg(node.pid, signal.SIGKILL)
            node.wait()
        table = process_table()
        leftovers = []
        for (pid, start), cmdline in self._seen.items():
            proc = table.get(pid)
            if proc is not None and proc.start == start:
                with contextlib.suppress(ProcessLookupError):
                    os.kill(pid, signal.SIGKILL)
                leftovers.append(f"{pid} {cmdline[:80]}")
        return leftovers
