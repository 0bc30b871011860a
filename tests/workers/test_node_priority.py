"""Moving a process tree to the idle scheduling class: every thread of every process, and what it starts later."""

from __future__ import annotations

import os
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path

import psutil
import pytest

from workers.node import idle_priority, thread_policies

# A parent with a second thread and a child; on a line from the test, the parent starts a thread and a
# second child, and both children report their own threads' classes.
TREE = """
import os, subprocess, sys, threading, time
CHILD = "import threading, time; threading.Thread(target=time.sleep, args=(600,)).start()"
threading.Thread(target=time.sleep, args=(600,), daemon=True).start()
first = subprocess.Popen([sys.executable, "-c", CHILD])
print(first.pid, flush=True)
sys.stdin.readline()
threading.Thread(target=time.sleep, args=(600,), daemon=True).start()
later = subprocess.Popen([sys.executable, "-c", CHILD])
print(later.pid, flush=True)
time.sleep(600)
"""


def in_idle_class(pid: int) -> list[bool]:
    return [policy == os.SCHED_IDLE for policy in thread_policies(pid).values()]


@pytest.fixture
def tree() -> Iterator[subprocess.Popen[str]]:
    parent = subprocess.Popen([sys.executable, "-c", TREE], stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True)
    try:
        yield parent
    finally:
        for process in psutil.Process(parent.pid).children(recursive=True):
            process.kill()
        parent.kill()
        parent.wait()
        for stream in (parent.stdin, parent.stdout):
            if stream:
                stream.close()


@pytest.mark.skipif(not Path("/proc/self/task").is_dir(), reason="per-thread scheduling is read from Linux's /proc")
def test_every_thread_moves_and_what_the_tree_starts_later_starts_idle(tree: subprocess.Popen[str]) -> None:
    assert tree.stdin and tree.stdout
    first = int(tree.stdout.readline())
    assert set(in_idle_class(tree.pid)) == {False}
    moved = idle_priority(tree.pid)
    assert moved >= 3  # the parent's two threads and the first child's main thread at least
    assert set(in_idle_class(tree.pid)) == set(in_idle_class(first)) == {True}
    tree.stdin.write("go\n")
    tree.stdin.flush()
    later = int(tree.stdout.readline())
    assert set(in_idle_class(tree.pid)) == {True}  # the parent's new thread
    assert len(in_idle_class(later)) >= 1 and set(in_idle_class(later)) == {True}  # a process started after the move
    assert idle_priority(tree.pid) == 0  # nothing left to move
    assert idle_priority(2**22 + 12345) == 0  # no such process: nothing to do, no error
