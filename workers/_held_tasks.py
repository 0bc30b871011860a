"""Tasks begun and not awaited where they begin (a close whose caller was cancelled, a frame's acknowledgement,
a collection stopped as its episode moved on), held until they end.

asyncio keeps a task only weakly: one that nobody references can be collected before it ends, and one whose
error nobody reads is logged as "Task exception was never retrieved" when it is. ``hold`` does both chores in
one place, for the editor's, the screencast's, the episode's and the human page's background work alike.
"""

from __future__ import annotations

import asyncio
import functools
from collections.abc import Awaitable
from typing import Any, TypeVar

_T = TypeVar("_T")

HeldTasks = set[asyncio.Future[Any]]
"""Tasks held until they end; an owner that waits for or cancels its own at its end keeps a set of its own."""

_HELD: HeldTasks = set()
"""Tasks no owner waits for: they end by themselves (each is bounded, or suppresses what could hold it)."""


def hold(work: Awaitable[_T], held: HeldTasks | None = None) -> asyncio.Future[_T]:
    """``work`` as a task (itself, if it is one), referenced from ``held`` (default: this module's set) until it
    ends, when its error, if any, is read. Whoever awaits the task still gets its outcome."""
    task = asyncio.ensure_future(work)
    into = _HELD if held is None else held
    into.add(task)
    task.add_done_callback(functools.partial(_ended, into))
    return task


def _ended(held: HeldTasks, task: asyncio.Future[Any]) -> None:
    held.discard(task)
    if not task.cancelled():
        task.exception()  # read: an error of work nobody awaits is the owner's to report, or nobody's
