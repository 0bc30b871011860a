"""Hosts that share nothing, made on this machine by the test itself (root only).

Each host is a network namespace with one link (a veth pair whose other end is on a bridge in a
namespace of its own, the "LAN"), an address in 10.201.0.0/24 and a default route into that LAN,
which leads nowhere else: no traffic leaves the namespaces made here. Each host's processes also
get their own mount namespace (a tmpfs on /tmp, /dev/shm and the home folder ``/tmp/home``; the
checkout bind-mounted read-only), their own PID namespace (they see only each other; its first
process reaps orphans, and killing it kills every process of the host), and their own hostname.

A host's private files are reached from outside through ``/proc/PID/root`` of its first process
(``Host.path``): that is how a test writes a driver's config into its /tmp and reads its run
directory back, as an operator would by logging in. ``IsolatedHosts.close`` kills every host
(each PID namespace's first process) and deletes every namespace, whatever happened before.
"""

from __future__ import annotations

import contextlib
import os
import secrets
import shutil
import signal
import subprocess
import sys
import time
from collections.abc import Mapping, Sequence
from pathlib import Path
from types import TracebackType

from tests.conftest import REPO

SUBNET = "10.201.0"
"""The hosts' /24; host i is ``SUBNET.(i + 1)``. Private, and only ever inside namespaces made here."""

HOME = "/tmp/home"
"""Each host's home folder: inside its private /tmp."""

_INIT = (
    "import os, signal, sys\n"
    "signal.signal(signal.SIGCHLD, lambda *_: None)\n"
    "print('ready', flush=True)\n"
    "while True:\n"
    "    try:\n"
    "        os.wait()\n"
    "    except ChildProcessError:\n"
    "        signal.pause()\n"
)
"""The first process of a host's PID namespace: reaps the orphans reparented to it (Ray daemonises)."""

_MOUNTS = (
    "set -e\n"
    'hostname "$1"\n'
    "mount -t tmpfs -o mode=1777,size=1g sw-shm /dev/shm\n"
    "mkdir /dev/shm/.checkout\n"
    'mount --bind "$2" /dev/shm/.checkout\n'  # held aside: the checkout may be under /tmp (a CI clone)
    "mount -t tmpfs -o mode=1777,size=2g sw-tmp /tmp\n"
    "mkdir -p -m 700 /tmp/home\n"
    'mkdir -p "$2"\n'
    'mount --move /dev/shm/.checkout "$2"\n'
    'mount -o remount,bind,ro "$2"\n'
    "rmdir /dev/shm/.checkout\n"
    "shift 2\n"
    'exec "$@"\n'
)
"""Run in the host's fresh mount namespace before its first process: private /tmp, /dev/shm, home; the
checkout read-only."""

NEEDED_TOOLS = ("ip", "unshare", "nsenter", "mount")


def unavailable() -> str | None:
    """Why hosts cannot be made here (one reason), or None."""
    if os.geteuid() != 0:
        return "making network and mount namespaces needs root"
    missing = [tool for tool in NEEDED_TOOLS if shutil.which(tool) is None]
    if missing:
        return f"making namespaces needs {', '.join(missing)} (iproute2, util-linux)"
    return None


def _ip(*args: str) -> None:
    done = subprocess.run(["ip", *args], capture_output=True, text=True, timeout=30)
    if done.returncode != 0:
        raise RuntimeError(f"ip {' '.join(args)}: {done.stderr.strip()}")


class Host:
    """One host: its namespace, address, and the first process of its PID namespace."""

    def __init__(self, index: int, namespace: str, checkout: Path) -> None:
        self.index = index
        self.name = f"host-{index}"
        self.address = f"{SUBNET}.{index + 1}"
        self.namespace = namespace
        self.link = f"h{index}"
        """The LAN's end of this host's veth pair (in the LAN namespace)."""
        self._starter = subprocess.Popen(
            ["ip", "netns", "exec", namespace, "unshare", "--mount", "--propagation", "private", "--pid",
             "--fork", "--mount-proc", "--uts", "--", "sh", "-c", _MOUNTS, "mounts", self.name, str(checkout),
             sys.executable, "-c", _INIT],
            stdin=subprocess.DEVNULL, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
        )  # fmt: skip
        assert self._starter.stdout is not None
        line = self._starter.stdout.readline()
        if line.strip() != "ready":
            self._starter.kill()
            _, errors = self._starter.communicate(timeout=30)
            raise RuntimeError(f"{self.name} did not start: {line}{errors}")
        self.pid = self._init_pid()
        """The host's first process, as this machine's PID namespace numbers it."""

    def _init_pid(self) -> int:
        children = Path(f"/proc/{self._starter.pid}/task/{self._starter.pid}/children").read_text().split()
        (child,) = children  # unshare --fork: its one child is PID 1 of the new namespace
        return int(child)

    def path(self, inside: str | Path) -> Path:
        """Where a path of this host's private view is seen from the test."""
        return Path(f"/proc/{self.pid}/root") / str(inside).lstrip("/")

    def command(self, args: Sequence[str], env: Mapping[str, str] | None = None, cwd: str = "/tmp") -> list[str]:
        """``args`` run inside this host: its network, mounts, processes and hostname, a clean environment."""
        base = {"PATH": os.environ.get("PATH", "/usr/bin:/bin"), "HOME": HOME, "LANG": "C.UTF-8"}
        environment = [f"{key}={value}" for key, value in {**base, **(env or {})}.items()]
        return [
            "nsenter", "--target", str(self.pid), "--mount", "--net", "--pid", "--uts", f"--wd={cwd}", "--",
            "env", "-i", *environment, *args,
        ]  # fmt: skip

    def run(
        self, args: Sequence[str], env: Mapping[str, str] | None = None, timeout: float = 120, cwd: str = "/tmp"
    ) -> subprocess.CompletedProcess[str]:
        return subprocess.run(self.command(args, env, cwd), capture_output=True, text=True, timeout=timeout)

    def kill(self) -> None:
        """Kill every process of this host: SIGKILL to its PID namespace's first process takes them all."""
        with contextlib.suppress(ProcessLookupError):
            os.kill(self.pid, signal.SIGKILL)
        self._starter.communicate(timeout=30)  # also closes its pipes


class IsolatedHosts:
    """``count`` hosts on one LAN, all made (and all torn down) by this object."""

    def __init__(self, count: int, checkout: Path = REPO) -> None:
        self.tag = secrets.token_hex(3)
        self.lan = f"sw-{self.tag}-lan"
        self.namespaces: list[str] = []
        self.hosts: list[Host] = []
        try:
            self._add_namespace(self.lan)
            _ip("-n", self.lan, "link", "add", "br0", "type", "bridge")
            _ip("-n", self.lan, "link", "set", "br0", "up")
            for index in range(count):
                self.hosts.append(self._add_host(index, checkout))
        except BaseException:
            self.close()
            raise

    def _add_namespace(self, name: str) -> None:
        _ip("netns", "add", name)
        self.namespaces.append(name)
        _ip("-n", name, "link", "set", "lo", "up")

    def _add_host(self, index: int, checkout: Path) -> Host:
        namespace = f"sw-{self.tag}-h{index}"
        self._add_namespace(namespace)
        link = f"h{index}"
        _ip("-n", self.lan, "link", "add", link, "type", "veth", "peer", "name", "eth0", "netns", namespace)
        _ip("-n", self.lan, "link", "set", link, "master", "br0", "up")
        _ip("-n", namespace, "addr", "add", f"{SUBNET}.{index + 1}/24", "dev", "eth0")
        _ip("-n", namespace, "link", "set", "eth0", "up")
        # A default route into the LAN, as a host has: Ray finds its own address by it; nothing is beyond.
        _ip("-n", namespace, "route", "add", "default", "dev", "eth0")
        return Host(index, namespace, checkout)

    def cut(self, host: Host) -> None:
        """Take the host's link down (its LAN end): a network partition of that host alone."""
        _ip("-n", self.lan, "link", "set", host.link, "down")

    def mend(self, host: Host) -> None:
        _ip("-n", self.lan, "link", "set", host.link, "up")

    def close(self) -> None:
        """Kill every host's processes, then delete every namespace; each step runs whatever failed before."""
        for host in self.hosts:
            with contextlib.suppress(OSError, subprocess.TimeoutExpired):
                host.kill()
        for name in reversed(self.namespaces):
            deadline = time.monotonic() + 30
            while subprocess.run(["ip", "netns", "pids", name], capture_output=True, text=True).stdout.strip():
                if time.monotonic() > deadline:  # something outlived its host: should not happen, say so
                    raise RuntimeError(f"processes left in namespace {name}")
                time.sleep(0.1)
            subprocess.run(["ip", "netns", "del", name], capture_output=True)

    def __enter__(self) -> IsolatedHosts:
        return self

    def __exit__(
        self, exc_type: type[BaseException] | None, exc: BaseException | None, tb: TracebackType | None
    ) -> None:
        self.close()
