"""``hold``: background work is referenced until it ends, and its error is read there, not logged as lost."""

from __future__ import annotations

import asyncio
import gc
import logging

import pytest

from workers._held_tasks import HeldTasks, hold


async def test_a_held_task_stays_in_its_set_until_it_ends_and_its_error_is_read(
    caplog: pytest.LogCaptureFixture,
) -> None:
    held: HeldTasks = set()
    gate = asyncio.Event()

    async def fails() -> None:
        await gate.wait()
        raise ValueError("the page went away")

    task = hold(fails(), held)
    assert held == {task}
    gate.set()
    await asyncio.wait([task])
    assert held == set() and isinstance(task.exception(), ValueError)
    caplog.set_level(logging.ERROR, logger="asyncio")
    unread = hold(fails(), held)  # nobody reads this one's error: hold does
    await asyncio.wait([unread])
    del task, unread
    gc.collect()
    assert "never retrieved" not in caplog.text


async def test_a_task_handed_to_hold_is_the_one_held_and_a_cancelled_one_ends_quietly() -> None:
    never = asyncio.get_running_loop().create_future()
    waiting = asyncio.ensure_future(never)
    held: HeldTasks = set()
    assert hold(waiting, held) is waiting
    waiting.cancel()
    await asyncio.wait([waiting])
    assert held == set() and waiting.cancelled()
