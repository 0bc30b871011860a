"""A real cluster of `ray start` processes for a test: on loopback only, token authentication on as
docs/cluster.md's recipe has it, and every process it started killed afterwards (only those)."""

from __future__ import annotations

import contextlib
import os
import secrets
import shutil
import signal
import socket
import subprocess
import tempfile
from pathlib import Path

from tests.conftest import REPO
from tests.support.ray_loopback import RAY_START


class Cluster:
    """`ray start` processes sharing a temp dir of their own, so that only they are stopped afterwards."""

    def __init__(self, root: Path) -> None:
        self.temp_dir = Path(tempfile.mkdtemp(prefix="sw-ray-", dir="/tmp"))  # Ray's socket paths must be short
        self.token = root / "token"
        self.token.write_text(secrets.token_hex(32))
        with socket.socket() as probe:
            probe.bind(("127.0.0.1", 0))
            self.port = probe.getsockname()[1]
        self.address = f"127.0.0.1:{self.port}"

    def env(self, checkout: Path | None = None) -> dict[str, str]:
        """The driver's environment: the token at hand, no authentication mode set (it finds out)."""
        env = {**os.environ, "RAY_AUTH_TOKEN_PATH": str(self.token)}
        for name in ("RAY_AUTH_MODE", "RAY_ADDRESS", "RAY_ENABLE_WINDOWS_OR_OSX_CLUSTER"):
            env.pop(name, None)
        if checkout is not None:
            env["PYTHONPATH"] = str(checkout)
        return env

    def start(self, *args: str, checkout: Path | None = None) -> None:
        """`ray start` as docs/cluster.md's recipe says: token authentication on, the token from a file."""
        command = [*RAY_START, *args, "--num-cpus", "1", "--disable-usage-stats", "--temp-dir", str(self.temp_dir)]
        env = {**self.env(checkout), "RAY_AUTH_MODE": "token", "SCRATCHWORLD_TEST_CLUSTER": str(self.temp_dir)}
        done = subprocess.run(command, cwd=checkout or REPO, env=env, capture_output=True, text=True, timeout=120)
        assert done.returncode == 0, done.stdout + done.stderr

    def head(self) -> None:
        self.start("--head", "--port", str(self.port), "--include-dashboard=false", "--resources", '{"browser": 0}')

    def node(self, checkout: Path, browsers: int) -> None:
        self.start("--address", self.address, "--resources", f'{{"browser": {browsers}}}', checkout=checkout)

    def stop(self) -> None:
        """Kill every process of this cluster: all inherited its marker (Ray renames some, e.g. its agents)."""
        marker = f"SCRATCHWORLD_TEST_CLUSTER={self.temp_dir}".encode()
        for proc in Path("/proc").iterdir():
            with contextlib.suppress(OSError, ValueError):
                if proc.name.isdigit() and marker in (proc / "environ").read_bytes().split(b"\0"):
                    os.kill(int(proc.name), signal.SIGKILL)
        shutil.rmtree(self.temp_dir, ignore_errors=True)
