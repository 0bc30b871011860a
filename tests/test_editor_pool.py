"""The editor pool: editors open ahead of use, each serves one evaluation, nothing carries over."""

from __future__ import annotations

import time

from tests.projects import counter_project
from tests.test_evaluation import CHECK_CLEAN, LEAKY, evaluate
from workers import BrowserSession, EditorPool, Evaluator


async def test_editors_open_ahead_and_are_never_reused(session: BrowserSession) -> None:
    async with EditorPool(session, spare=1) as pool:
        async with pool.editor() as first:  # nothing was ready: opened directly, one spare started
            assert pool.opened == 2
        assert first.page.is_closed()
        await pool.wait_ready()
        started = time.monotonic()
        async with pool.editor() as second:
            waited = time.monotonic() - started
            assert second.context is not first.context
            assert second.ready_s is not None and waited < second.ready_s / 2  # it had started up already
            status = await second.status()
            assert status.vm and status.workspace and status.renderer
        assert pool.opened == 3
        spare = list(pool._opening)
    assert all(task.done() for task in spare)  # closing the pool closes what it prepared
    assert all(task.cancelled() or task.exception() or task.result().page.is_closed() for task in spare)


async def test_nothing_leaks_between_pooled_evaluations(session: BrowserSession) -> None:
    async with EditorPool(session, spare=1) as pool:
        evaluator = Evaluator(session, pool)
        first = await evaluate(evaluator, LEAKY, counter_project("Other"))
        assert first.success
        second = await evaluate(evaluator, CHECK_CLEAN, counter_project("Counter"))
    assert second.error is None
    assert [t.name for t in second.tests if not t.passed] == [], second.tests
