"""A driver's remote run directory: the lease held, the mirror brought level, and every commit copied up.

``RemoteRun`` is what ``run_sweep`` opens for ``output: s3://...``. It is the run store's listener: each committed
journal entry, compacted segment and stored artifact is handed to the uploader as it happens, and the scheduler
never waits for the network. An outage leaves the sweep running; the uploads wait and catch up, and ``close`` says
what is still pending (the next run from the same mirror pushes it).
"""

from __future__ import annotations

import time
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING

from scratchworld_dist._errors import RunDirError
from scratchworld_dist.results.remote._lease import Lease, LeaseRecord
from scratchworld_dist.results.remote._location import RemoteLocation, parse_location, redact
from scratchworld_dist.results.remote._mirror import (
    check_mirror,
    default_mirror,
    entry_key,
    mark_mirror,
    mirror_token,
    pull,
    push_missing,
    remote_files,
    segment_folder,
)
from scratchworld_dist.results.remote._uploader import Uploader

if TYPE_CHECKING:
    from fsspec import AbstractFileSystem
    from rich.console import Console

    from scratchworld_dist.sweep import SweepConfig

Say = Callable[[str], None]


def unreachable(location: RemoteLocation, exc: BaseException) -> RunDirError:
    """The one-line error for a bucket that cannot take the run (missing, refusing writes, unreachable)."""
    reason = " ".join(str(exc).split()) or type(exc).__name__
    if isinstance(exc, FileNotFoundError):
        what = "the bucket does not exist"
    elif isinstance(exc, PermissionError):
        what = "the store refuses writes"
    else:
        what = "the store cannot be reached"
    return RunDirError(redact(f"{location.url}: cannot write results here: {what} ({reason[:200]})"))


class RemoteRun:
    """The remote side of one driver's session on a run directory."""

    def __init__(self, location: RemoteLocation, fs: AbstractFileSystem, mirror: Path, say: Say) -> None:
        self.location = location
        self.fs = fs
        self.mirror = mirror
        self.say = say
        self.uploader = Uploader(fs, self._problem)
        self.lease: Lease | None = None
        self.pulled = False
        self.pulled_entries = 0
        self.pushed = 0

    @classmethod
    def open(cls, url: str, cache_dir: Path | None, lease_ttl_s: float, say: Say) -> RemoteRun:
        """Take the run's lease and bring the local mirror level with the bucket; ``RunDirError`` in one line for
        a bucket that does not exist, refuses writes or cannot be reached, and for a run another driver holds."""
        location = parse_location(url)
        fs = location.filesystem()
        mirror = default_mirror(location, cache_dir)
        check_mirror(mirror, location)
        run = cls(location, fs, mirror, say)
        lease = Lease(fs, location, lease_ttl_s)
        try:
            before = lease.acquire()
        except RunDirError:
            run.uploader.close(0)
            raise
        except Exception as exc:  # s3fs/botocore/aiohttp errors of every kind: the bucket cannot take the run
            run.uploader.close(0)
            raise unreachable(location, exc) from None
        run.lease = lease
        try:
            run._level(before)
        except Exception as exc:
            run.close(0)
            if isinstance(exc, RunDirError):
                raise
            raise unreachable(location, exc) from None
        return run

    def _level(self, before: LeaseRecord | None) -> None:
        assert self.lease is not None
        trusted = before is not None and before.token == mirror_token(self.mirror)
        fresh = before is None and not any(f != "lease.json" for f in remote_files(self.fs, self.location))
        if trusted or fresh:
            self.mirror.mkdir(parents=True, exist_ok=True)
            self.pushed = push_missing(self.fs, self.location, self.mirror, self.uploader)
        else:
            self.pulled = True
            self.pulled_entries = pull(self.fs, self.location, self.mirror)
        mark_mirror(self.mirror, self.location, self.lease.record.token)

    def describe(self) -> str:
        """One line for the console: where the results go and how the mirror was brought level."""
        if self.pulled:
            how = f"rebuilt from the bucket, {self.pulled_entries} uncompacted journal entry(ies) among it"
        elif self.pushed:
            how = f"{self.pushed} file(s) the bucket lacked pushed from it"
        else:
            how = "level with the bucket"
        return f"results -> {self.location.url} (local mirror {self.mirror}, {how})"

    # -- the run store's listener ---------------------------------------------------------

    def _lost(self) -> bool:
        """Whether another driver holds the run now: nothing more is put there from this session."""
        return self.lease is not None and self.lease.lost_to is not None

    def committed(self, segment: int, line: int, data: bytes) -> None:
        if self._lost():
            return
        self.uploader.put_bytes(self.location.key(entry_key(segment, line)), data, committed_at=time.monotonic())

    def compacted(self, segment: int, tables: list[str]) -> None:
        """A segment's shards (``jobs`` last, as written), then its journal entries removed."""
        if self._lost():
            return
        for table in tables:
            relative = f"{table}/part-{segment:06d}.parquet"
            self.uploader.put_file(self.location.key(relative), self.mirror / relative)
        self.uploader.delete_folder(self.location.key(segment_folder(segment)))

    def stored(self, relative: str) -> None:
        """An artifact, a shared image, the manifest, the events, a report: put as the file is when sent."""
        if self._lost():
            return
        self.uploader.put_file(self.location.key(relative), self.mirror / relative)

    # -- the end --------------------------------------------------------------------------

    def push_rest(self) -> None:
        """At the end of a session: every file of the mirror the bucket lacks (the memory a sweep keeps, written
        by its own service) and the events. An unreachable store leaves them to the next run."""
        if self._lost():
            return
        try:
            push_missing(self.fs, self.location, self.mirror, self.uploader)
        except Exception:  # the uploads already waiting say why; the next run from this mirror pushes the rest
            return

    def pending_note(self) -> str | None:
        """What is not in the bucket yet, and why (None: everything is)."""
        pending = self.uploader.pending()
        lost = self.lease.lost_to if self.lease is not None else None
        if lost is not None:
            return redact(
                f"{self.location.url}: another driver took this run's lease while its store was unreachable ({lost}); "
                f"{pending} upload(s) not sent, this session's results stay in {self.mirror}"
            )
        if not pending:
            return None
        why = f" ({self.uploader.problem})" if self.uploader.problem else ""
        return redact(
            f"uploads: {pending} file(s) not yet in {self.location.url}{why}; they are kept in {self.mirror} and "
            "pushed by the next run of this config from this machine"
        )

    def close(self, drain_timeout_s: float) -> str | None:
        """Wait at most ``drain_timeout_s`` for the uploads, release the lease; the pending note, if any."""
        self.uploader.drain(drain_timeout_s)
        note = self.pending_note()
        self.uploader.close(0)
        if self.lease is not None:
            if note is None:
                self.lease.release()
            else:  # a lease left to expire: another machine's driver must not start from an incomplete bucket
                self.lease.stop_renewing()
        return note

    def _problem(self, reason: str | None, pending: int) -> None:
        if reason is not None:
            where = self.location.url
            self.say(redact(f"uploads to {where} are failing ({reason}); the sweep goes on, {pending} waiting"))
        else:
            self.say(f"uploads to {self.location.url} go through again; {pending} still to send")


def put_once(url: str, relative: str, data: bytes) -> str | None:
    """Put one file (the report written after the sweep) in the remote run; a one-line note if it failed."""
    location = parse_location(url)
    try:
        location.filesystem().pipe_file(location.key(relative), data)
    except Exception as exc:
        return redact(f"{location.url}/{relative}: not uploaded ({' '.join(str(exc).split())[:200]})")
    return None


def open_remote(config: SweepConfig, console: Console) -> RemoteRun | None:
    """The remote side of a sweep whose ``output`` is a URL (None: a local run directory), said on the console."""
    url = config.remote_output()
    if url is None:
        return None

    def say(line: str) -> None:
        console.print(line, markup=False)

    storage = config.storage
    run = RemoteRun.open(url, storage.cache_dir, storage.lease_ttl_s, say)
    say(run.describe())
    return run
