"""docs/cluster.md's recipe on hosts that share nothing (``tests/support/netns_hosts.py``).

The head (no browsers) runs on the first host, beside the driver (a Ray driver attaches to a node of its
own host); worker nodes run on the others. Every node is plain ``ray start`` on its host's address, with
token authentication on and the head's token copied into each host's home, as the recipe says. The head
notices a lost node within seconds (``HEALTH_CHECKS``).
"""

from __future__ import annotations

import json
import secrets
import subprocess
import sys
from collections.abc import Mapping
from pathlib import Path

from tests.support.netns_hosts import HOME, Host

RAY = str(Path(sys.executable).with_name("ray"))
SCRATCHWORLD = str(Path(sys.executable).with_name("scratchworld"))
PORT = 6379
"""The head's GCS port: the hosts' ports are their own, so the recipe's default serves."""

HEALTH_CHECKS = {"health_check_period_ms": 1000, "health_check_timeout_ms": 2000, "health_check_failure_threshold": 5}
"""The head declares a silent node dead after five failed checks, each waiting 2 s for an answer (about 15 s;
Ray's defaults take longer), and a merely busy node on a loaded machine is still given its 2 s."""

NODE_ENV = {"RAY_AUTH_MODE": "token", "PYTHONDONTWRITEBYTECODE": "1"}
"""Every node's environment: token authentication on (recipe step 4); nothing written into the checkout."""

_WAIT_FOR_NODES = (
    "import json, sys, time\n"
    "from ray._raylet import GcsClient\n"
    "client = GcsClient(address=sys.argv[1])\n"
    "want, slots, end = int(sys.argv[2]), float(sys.argv[3]), time.monotonic() + float(sys.argv[4])\n"
    "while time.monotonic() < end:\n"
    "    alive = [n for n in client.get_all_node_info().values() if n.state == 0]\n"
    "    if len(alive) >= want and sum(n.resources_total.get('browser', 0) for n in alive) >= slots:\n"
    "        sys.exit(0)\n"
    "    time.sleep(0.2)\n"
    "sys.exit(1)\n"
)
"""Polls the head's node table (no driver attaches) until the cluster shows the nodes it should."""


class HostCluster:
    """A Ray cluster over isolated hosts: ``head`` on the driver's host, ``node`` on each other one."""

    def __init__(self, driver_host: Host) -> None:
        self.driver_host = driver_host
        self.address = f"{driver_host.address}:{PORT}"
        self.token = secrets.token_hex(32)
        self.nodes: dict[str, Host] = {}

    def _give_token(self, host: Host) -> None:
        """Recipe step 3: the head's token at ``~/.ray/auth_token`` on every host."""
        folder = host.path(HOME) / ".ray"
        folder.mkdir(mode=0o700, exist_ok=True)
        (folder / "auth_token").write_text(self.token)

    def _start(self, host: Host, *args: str, env: Mapping[str, str] | None = None) -> None:
        self._give_token(host)
        command = [RAY, "start", f"--node-ip-address={host.address}", "--num-cpus=1", "--disable-usage-stats", *args]
        done = host.run(command, {**NODE_ENV, **(env or {})}, timeout=180)
        if done.returncode != 0:
            raise RuntimeError(f"ray start on {host.name} failed:\n{done.stdout}{done.stderr}")

    def head(self) -> None:
        config = json.dumps(HEALTH_CHECKS)
        self._start(
            self.driver_host, "--head", f"--port={PORT}", "--include-dashboard=false",
            "--resources", '{"browser": 0}', f"--system-config={config}",
        )  # fmt: skip

    def node(self, host: Host, browsers: int, env: Mapping[str, str] | None = None) -> None:
        """A worker node; ``env``: more of its environment, which its workers inherit (a model's key)."""
        self._start(host, f"--address={self.address}", "--resources", json.dumps({"browser": browsers}), env=env)
        self.nodes[host.name] = host

    def wait_for(self, nodes: int, browsers: int, timeout_s: float = 120) -> None:
        """Block until the head shows ``nodes`` live nodes offering ``browsers`` slots in all."""
        probe = [sys.executable, "-c", _WAIT_FOR_NODES, self.address, str(nodes), str(browsers), str(timeout_s)]
        done = self.driver_host.run(probe, NODE_ENV, timeout=timeout_s + 30)
        if done.returncode != 0:
            raise RuntimeError(f"the cluster at {self.address} did not show {nodes} node(s): {done.stderr[-2000:]}")

    def driver(
        self, config: str, log: Path, *args: str, env: Mapping[str, str] | None = None
    ) -> subprocess.Popen[bytes]:
        """``scratchworld run CONFIG`` on the driver's host (``config``: a path there), its output in ``log``
        (a path of the test's): started outside the checkout, with the token in its home."""
        environment = {"PYTHONDONTWRITEBYTECODE": "1", **(env or {})}
        command = self.driver_host.command([SCRATCHWORLD, "run", config, *args], environment)
        with log.open("wb") as out:
            return subprocess.Popen(command, stdout=out, stderr=subprocess.STDOUT)
