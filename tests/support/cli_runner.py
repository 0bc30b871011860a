"""`scratchworld` through its real entry point (``main``, which ends in ``sys.exit``), in the test's process.

Click's test runner captures what it prints; this saves booting Python (and importing Ray, Playwright
and LiteLLM) for each command. Tests of what only a process shows (killing or resuming a driver, a
server that must outlive its caller) run it as a process instead (``tests/support/sweep_driver.py``).
"""

from __future__ import annotations

import sys
from dataclasses import dataclass

import pytest
from click.testing import CliRunner

from scratchworld_dist.cli import main


@dataclass(frozen=True)
class Done:
    """What one command did: its exit status and what it printed."""

    returncode: int
    stdout: str
    stderr: str


def invoke(*args: str) -> Done:
    """Run ``scratchworld ARGS...`` here; ``sys.argv`` is restored afterwards."""
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(sys, "argv", ["scratchworld", *args])
        with CliRunner().isolation() as (out, err, _), pytest.raises(SystemExit) as exited:
            main()
    code = exited.value.code
    return Done(code if isinstance(code, int) else 0, out.getvalue().decode(), err.getvalue().decode())
