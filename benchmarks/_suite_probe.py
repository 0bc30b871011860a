"""pytest plugin for ``benchmarks/suite_time.py``: when each test starts and ends, per test process.

Each process (``gw0``, ``gw1``, or ``main`` without xdist) appends ``S|E <tab> time <tab> node id``
lines to its own file in ``$SUITE_PROBE_DIR``; a line is written and the file closed at once, so a
killed run keeps what it measured.
"""

from __future__ import annotations

import os
import time
from pathlib import Path

import pytest

_FILE: Path | None = None
"""This process's file, or None: no probe folder, or the xdist controller (which only relays)."""


def pytest_configure(config: pytest.Config) -> None:
    global _FILE
    folder = os.environ.get("SUITE_PROBE_DIR")
    relays = not hasattr(config, "workerinput") and (getattr(config.option, "numprocesses", 0) or 0) > 0
    if folder and not relays:
        _FILE = Path(folder) / f"{os.environ.get('PYTEST_XDIST_WORKER', 'main')}.tsv"


def _note(kind: str, nodeid: str) -> None:
    if _FILE is not None:
        with _FILE.open("a") as out:
            out.write(f"{kind}\t{time.time():.3f}\t{nodeid}\n")


def pytest_runtest_logstart(nodeid: str, location: tuple[str, int | None, str]) -> None:
    _note("S", nodeid)


def pytest_runtest_logfinish(nodeid: str, location: tuple[str, int | None, str]) -> None:
    _note("E", nodeid)
