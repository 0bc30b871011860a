"""Upstream ScratchWorld projects, evaluated through the upstream script contract."""

from __future__ import annotations

from pathlib import Path

import pytest

from scratchworld_dist import load_suite, validate_tasks

pytestmark = pytest.mark.browser


@pytest.mark.slow
async def test_upstream_projects_under_the_upstream_contract(upstream_clone: Path) -> None:
    suite = load_suite(upstream_clone)
    tasks = suite.select(ids=["say_hello", "calculate_gcd", "pong_starter_touching_red_error"])
    rows = {row.task_id: row for row in await validate_tasks(tasks, parallel=2)}

    hello = rows["say_hello"]
    assert hello.golden is not None and hello.golden.success  # full report with counts
    assert not hello.initial.success and hello.initial.error is None

    gcd = rows["calculate_gcd"]  # details-only report: counts derived by the evaluator
    assert gcd.golden is not None and (gcd.golden.passed, gcd.golden.total) == (3, 3)
    assert (gcd.initial.passed, gcd.initial.total) == (0, 3)

    # A big debug project (pong, 250 KB with sounds and bitmaps) loads into a clean VM.
    pong = rows["pong_starter_touching_red_error"]
    assert pong.golden is not None and pong.golden.success and pong.initial.success
    assert pong.failures() == ["debug initial already passes"]  # our stand-in script cannot tell them apart
