"""A background uploader: puts files in a remote run directory in the order they were handed over, without ever
making the caller wait.

The scheduler's loop commits a journal entry and hands its bytes here; a thread of its own puts it in the bucket,
retrying with backoff (tenacity) for as long as the store refuses or is unreachable. Items leave in order (the
journal entries of a segment before its shards, its ``jobs`` shard last, then the entries' deletion), so a reader
of the bucket never sees a segment both ways or neither. While an item keeps failing the queue waits behind it;
``pending`` and ``problem`` say what is held up and why.
"""

from __future__ import annotations

import contextlib
import threading
import time
from collections import deque
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

from tenacity import RetryCallState, Retrying, retry_if_exception, stop_when_event_set, wait_exponential_jitter

if TYPE_CHECKING:
    from fsspec import AbstractFileSystem


@dataclass
class _Item:
    key: str
    """The fsspec path put (or, for a deletion, the folder removed)."""

    data: bytes | None = None
    source: Path | None = None
    """A local file read when the item is sent (the manifest, rewritten in place, goes as it is then)."""

    delete: bool = False
    committed_at: float | None = None
    """``time.monotonic()`` when the entry was committed locally (its upload lag is measured from there)."""

    queued_at: float = field(default_factory=time.monotonic)


def _one_line(exc: BaseException) -> str:
    text = " ".join(str(exc).split()) or type(exc).__name__
    return f"{type(exc).__name__}: {text}"[:300]


class Uploader:
    """One thread putting files in ``fs`` in order; ``close`` waits a bounded time for the rest."""

    def __init__(self, fs: AbstractFileSystem, on_problem: Callable[[str | None, int], None] | None = None) -> None:
        """``on_problem(reason, pending)``: told when uploads start failing (reason) and when they go through again
        (None), from the uploader's thread."""
        self.fs = fs
        self.on_problem = on_problem
        self.problem: str | None = None
        self.lags: list[float] = []
        """Seconds from a journal entry's local commit to its object in the bucket, in commit order."""
        self.dropped: list[str] = []
        """Local files gone before they could be sent (a compacted-away temp file...)."""
        self._items: deque[_Item] = deque()
        self._queued_files: set[str] = set()
        self._changed = threading.Condition()
        self._stopping = threading.Event()
        self._busy = False
        self._thread = threading.Thread(target=self._run, name="scratchworld-uploader", daemon=True)
        self._thread.start()

    # -- handing over (never blocks on the network) ------------------------------------

    def put_bytes(self, key: str, data: bytes, *, committed_at: float | None = None) -> None:
        self._push(_Item(key=key, data=data, committed_at=committed_at))

    def put_file(self, key: str, source: Path) -> None:
        """Put ``source`` as it is when sent; a file already waiting to go is not queued twice."""
        with self._changed:
            if key in self._queued_files:
                return
            self._queued_files.add(key)
        self._push(_Item(key=key, source=source))

    def delete_folder(self, key: str) -> None:
        self._push(_Item(key=key, delete=True))

    def _push(self, item: _Item) -> None:
        with self._changed:
            self._items.append(item)
            self._changed.notify_all()

    # -- state ---------------------------------------------------------------------------

    def pending(self) -> int:
        """Items not yet in the bucket (the one being sent included)."""
        with self._changed:
            return len(self._items)

    def drain(self, timeout: float | None) -> bool:
        """Wait until everything handed over is in the bucket, at most ``timeout`` seconds; whether it is."""
        with self._changed:
            return self._changed.wait_for(lambda: not self._items, timeout)

    def close(self, timeout: float | None) -> int:
        """Drain for at most ``timeout`` seconds, then stop; the number of items left unsent."""
        self.drain(timeout)
        self._stopping.set()
        with self._changed:
            self._changed.notify_all()
        self._thread.join()
        return self.pending()

    # -- the thread ----------------------------------------------------------------------

    def _run(self) -> None:
        while True:
            with self._changed:
                self._changed.wait_for(lambda: self._items or self._stopping.is_set())
                if self._stopping.is_set():
                    return
                item = self._items[0]
            try:
                self._send_with_retries(item)
            except Exception:  # stopped while failing: the item stays pending
                if self._stopping.is_set():
                    return
                raise
            with self._changed:
                self._items.popleft()
                if item.source is not None:
                    self._queued_files.discard(item.key)
                self._changed.notify_all()
            if item.committed_at is not None:
                self.lags.append(time.monotonic() - item.committed_at)

    def _send_with_retries(self, item: _Item) -> None:
        retrying = Retrying(
            retry=retry_if_exception(lambda exc: isinstance(exc, Exception)),  # the store's every refusal: again
            wait=wait_exponential_jitter(multiplier=0.1, max=5.0),
            stop=stop_when_event_set(self._stopping),
            before_sleep=self._failed,
            reraise=True,
        )
        for attempt in retrying:
            with attempt:
                self._send(item)
        if self.problem is not None:
            self.problem = None
            if self.on_problem is not None:
                self.on_problem(None, self.pending())

    def _send(self, item: _Item) -> None:
        if item.delete:
            with contextlib.suppress(FileNotFoundError):  # already gone (a retried deletion, or never uploaded)
                self.fs.rm(item.key, recursive=True)
            return
        data = item.data
        if data is None:
            try:
                data = item.source.read_bytes()  # type: ignore[union-attr]
            except (FileNotFoundError, IsADirectoryError):  # the local file is gone: nothing left to send
                self.dropped.append(item.key)
                return
        self.fs.pipe_file(item.key, data)  # one PUT: the object appears whole or not at all

    def _failed(self, state: RetryCallState) -> None:
        exc = state.outcome.exception() if state.outcome is not None else None
        reason = _one_line(exc) if exc is not None else "unknown"
        first = self.problem is None
        self.problem = reason
        if first and self.on_problem is not None:
            self.on_problem(reason, self.pending())
