"""Moving a browser to Linux's idle scheduling class, so that the work of other browsers on the node goes first.

A thread in ``SCHED_IDLE`` runs only on CPU time that threads of the normal class leave over
(its weight is under a third of a percent of a default thread's). Niceness would not hold:
Chromium sets its threads' nice values itself (e.g. -8 for display threads when it may), but it
leaves the scheduling class alone (but for realtime audio threads, which it moves to ``SCHED_RR``
when it may), and a new thread or process starts in its creator's class. So every thread of the
browser's processes moves, and the renderers Chromium forks later (from its zygote) and the
processes it launches later (from its browser process) start in the class too.
Moving into the class needs no privilege, and nothing here ever moves a thread out of it.
"""

from __future__ import annotations

import contextlib
import os
from pathlib import Path

import psutil

MAX_PASSES = 5
"""Walks over the tree at most: a pass that moves nothing found every thread then alive in the class
(Chromium may still move an audio thread to ``SCHED_RR`` later, see above)."""


def idle_priority(root_pid: int) -> int:
    """Move ``root_pid`` and its descendants, every thread, to ``SCHED_IDLE``; the number of threads moved
    (0 where the system has no such class: the browser then runs at normal priority).

    A thread (or process) started during a pass by one not yet moved starts in the normal class, so the
    tree is walked again until a pass moves nothing (seen: a browser a moment after its launch)."""
    if not hasattr(os, "SCHED_IDLE"):
        return 0
    total = 0
    for _ in range(MAX_PASSES):
        moved = _move_once(root_pid)
        total += moved
        if moved == 0:
            break
    return total


def _move_once(root_pid: int) -> int:
    try:
        root = psutil.Process(root_pid)
        processes = [root, *root.children(recursive=True)]
    except psutil.Error:
        return 0
    moved = 0
    for process in processes:
        for tid in _threads(process.pid):
            with contextlib.suppress(OSError):  # the thread ended meanwhile
                if os.sched_getscheduler(tid) != os.SCHED_IDLE:
                    os.sched_setscheduler(tid, os.SCHED_IDLE, os.sched_param(0))
                    moved += 1
    return moved


def thread_policies(pid: int) -> dict[int, int]:
    """The scheduling policy (``os.SCHED_*``, Linux) of each thread of ``pid``, by thread id."""
    policies = {}
    for tid in _threads(pid):
        with contextlib.suppress(OSError):
            policies[tid] = os.sched_getscheduler(tid)
    return policies


def _threads(pid: int) -> list[int]:
    """The process's thread ids (each its own scheduling entity on Linux)."""
    try:
        return [int(entry.name) for entry in Path(f"/proc/{pid}/task").iterdir()]
    except OSError:
        return [pid]
