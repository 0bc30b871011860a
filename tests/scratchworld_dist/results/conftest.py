"""The results tests' store: a run directory opened for writing, closed after the test."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import pytest

from scratchworld_dist.results import RunStore


@pytest.fixture
def writer(tmp_path: Path) -> Iterator[RunStore]:
    store = RunStore(tmp_path / "run")
    store.open_for_writing()
    yield store
    store.close()
