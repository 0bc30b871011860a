"""The lease object that keeps a second driver off a remote run directory another driver is writing.

A local run directory is held by ``flock``; a bucket has no locks, so the writer keeps ``lease.json`` there and
renews it from a thread. Another driver is refused while the lease is live, with a message that says whose it is
(host, pid, since). A lease whose holder stopped renewing expires after ``ttl_s``; one held by a process of this
host that no longer exists is taken over at once. A clean stop marks the lease released; it stays in the bucket
as the record of who wrote last (a driver's local mirror is trusted only if it was that writer's).
"""

from __future__ import annotations

import os
import socket
import threading
import uuid
from datetime import UTC, datetime, timedelta
from typing import TYPE_CHECKING

import psutil
from pydantic import BaseModel, ValidationError

from scratchworld_dist._errors import RunDirError
from scratchworld_dist.results.remote._location import RemoteLocation

if TYPE_CHECKING:
    from fsspec import AbstractFileSystem

LEASE_NAME = "lease.json"


class LeaseRecord(BaseModel):
    """What ``lease.json`` holds."""

    token: str
    """The writing session's id (a fresh one each run)."""

    host: str
    pid: int
    since: datetime
    renewed: datetime
    ttl_s: float
    released: bool = False

    def expires(self) -> datetime:
        return self.renewed + timedelta(seconds=self.ttl_s)

    def live(self) -> bool:
        """Whether its holder may still be writing."""
        if self.released or datetime.now(tz=UTC) >= self.expires():
            return False
        return self.host != socket.gethostname() or psutil.pid_exists(self.pid)

    def holder(self) -> str:
        return f"host {self.host}, pid {self.pid}, since {self.since.isoformat(timespec='seconds')}"


class Lease:
    """This driver's lease on a remote run directory."""

    def __init__(self, fs: AbstractFileSystem, location: RemoteLocation, ttl_s: float) -> None:
        self.fs = fs
        self.location = location
        self.key = location.key(LEASE_NAME)
        now = datetime.now(tz=UTC)
        self.record = LeaseRecord(
            token=uuid.uuid4().hex, host=socket.gethostname(), pid=os.getpid(), since=now, renewed=now, ttl_s=ttl_s
        )
        self.renew_error: str | None = None
        self.lost_to: str | None = None
        """Who took the lease while this driver held it (it expired during an outage); None while it holds."""
        self._stop = threading.Event()
        self._thread: threading.Thread | None = None

    def read(self) -> LeaseRecord | None:
        """The lease in the bucket now (None: there is none); ``OSError`` when the bucket cannot be read."""
        try:
            data = self.fs.cat_file(self.key)
        except FileNotFoundError:
            return None
        try:
            return LeaseRecord.model_validate_json(data)
        except ValidationError:
            raise RunDirError(f"{self.location.url}/{LEASE_NAME}: not a scratchworld lease; move it away") from None

    def acquire(self) -> LeaseRecord | None:
        """Take the lease (``RunDirError`` naming the holder of a live one); the record it replaced."""
        before = self.read()
        if before is not None and before.token != self.record.token and before.live():
            raise RunDirError(
                f"{self.location.url}: another scratchworld run is writing here ({before.holder()}); its lease "
                f"expires at {before.expires().isoformat(timespec='seconds')} unless that run renews it"
            )
        self._write()
        found = self.read()  # two drivers that took it at once: the one whose write landed last keeps it
        if found is None or found.token != self.record.token:
            who = found.holder() if found is not None else "its lease vanished"
            raise RunDirError(f"{self.location.url}: another scratchworld run took the lease at the same time ({who})")
        self._thread = threading.Thread(target=self._keep, name="scratchworld-lease", daemon=True)
        self._thread.start()
        return before

    def stop_renewing(self) -> None:
        """Let the lease expire (a driver that stops with uploads pending keeps other machines off until then)."""
        self._stop.set()
        if self._thread is not None:
            self._thread.join()
            self._thread = None

    def release(self) -> None:
        """Stop renewing and mark the lease released (best effort: an unreachable store lets it expire)."""
        self.stop_renewing()
        if self.lost_to is not None:
            return
        self.record = self.record.model_copy(update={"released": True, "renewed": datetime.now(tz=UTC)})
        try:
            self._write()
        except Exception:  # unreachable now: the lease expires after its term instead
            self.renew_error = "not released (the store was unreachable)"

    def _write(self) -> None:
        self.fs.pipe_file(self.key, self.record.model_dump_json().encode())

    def _keep(self) -> None:
        """Renew a third of the way through each term, until released."""
        while not self._stop.wait(self.record.ttl_s / 3):
            self.record = self.record.model_copy(update={"renewed": datetime.now(tz=UTC)})
            try:
                found = self.read()
                if found is not None and found.token != self.record.token:  # expired while unreachable, and taken
                    self.lost_to = found.holder()
                    return
                self._write()
                self.renew_error = None
            except Exception as exc:  # the store is down: keep the sweep going, try again next term
                self.renew_error = " ".join(str(exc).split())[:200] or type(exc).__name__
