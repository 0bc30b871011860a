"""`scratchworld run` as a test drives it: a subprocess in its own process group, its output in a log file.

Every driver is killed with its whole group after the test (the ``drivers`` fixture of conftest),
so a killed driver's Ray helpers never outlive it. A test that neither kills nor signals its driver,
nor needs its workers to see an environment of its own, runs it in its own process instead (``run_here``);
workers that call a test model server find it in the environment of the module's ``model_ray``.
"""

from __future__ import annotations

import contextlib
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

from tests.conftest import REPO
from tests.support.cli_runner import invoke

SCRATCHWORLD = str(Path(sys.executable).with_name("scratchworld"))


class Driver:
    """A `scratchworld run` process in its own process group, its output in a log file."""

    def __init__(self, config: Path, *args: str) -> None:
        self.log = config.with_name(f"driver-{time.monotonic_ns()}.log")
        with self.log.open("w") as out:
            self.process = subprocess.Popen(
                [SCRATCHWORLD, "run", str(config), *args],
                stdout=out,
                stderr=subprocess.STDOUT,
                cwd=REPO,
                start_new_session=True,
            )

    def wait(self, timeout: float = 300) -> tuple[int, str]:
        code = self.process.wait(timeout)
        return code, self.log.read_text()

    def kill_group(self) -> None:
        with contextlib.suppress(ProcessLookupError):
            os.killpg(self.process.pid, signal.SIGKILL)
        self.process.wait()


def run(drivers: list[Driver], config: Path, *args: str, timeout: float = 300) -> tuple[int, str]:
    driver = Driver(config, *args)
    drivers.append(driver)
    return driver.wait(timeout)


def run_here(config: Path, *args: str) -> tuple[int, str]:
    """The driver in this process, on the module's Ray (``shared_ray`` or ``model_ray``): exit code and output."""
    done = invoke("run", str(config), *args)
    return done.returncode, done.stdout + done.stderr
