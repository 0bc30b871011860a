"""Reading the files a user names (configs, suite files, scripts, trajectories, projects), bounded.

A path can name something that is not a file of reasonable size: ``/dev/zero`` or a runaway
file would be read until memory runs out, and opening a FIFO blocks until someone writes to it.
Such a path is refused here with an ``OSError`` that names it, which every caller already turns
into a one-line error about that file.
"""

from __future__ import annotations

import errno
import os
import shutil
import stat
from pathlib import Path

MIB = 1024 * 1024
MAX_TEXT_BYTES = 16 * MIB
"""The largest config, suite file, script or trajectory read (real ones are kilobytes)."""


class FileTooLargeError(OSError):
    """A file over the size its reader accepts."""

    def __init__(self, path: Path, limit: int) -> None:
        size = f"{limit / MIB:g} MiB" if limit >= MIB else f"{limit} bytes"
        super().__init__(errno.EFBIG, f"larger than {size}", str(path))
        self.limit = limit


def read_file(path: Path, limit: int = MAX_TEXT_BYTES) -> bytes:
    """The bytes of the regular file at ``path``, at most ``limit`` of them; raises ``OSError`` otherwise."""
    # Non-blocking, so that opening a FIFO returns at once instead of waiting for a writer.
    descriptor = os.open(path, os.O_RDONLY | os.O_NONBLOCK)
    with os.fdopen(descriptor, "rb") as handle:
        mode = os.fstat(descriptor).st_mode
        if stat.S_ISDIR(mode):
            raise IsADirectoryError(errno.EISDIR, os.strerror(errno.EISDIR), str(path))
        if not stat.S_ISREG(mode):
            raise OSError(errno.EINVAL, "not a regular file (a device, FIFO or socket)", str(path))
        data = handle.read(limit + 1)
    if len(data) > limit:
        raise FileTooLargeError(path, limit)
    return data


def read_text(path: Path, limit: int = MAX_TEXT_BYTES) -> str:
    """The UTF-8 text of the regular file at ``path``; raises ``OSError`` or ``UnicodeDecodeError``."""
    return read_file(path, limit).decode("utf-8")


def write_atomic(path: Path, data: bytes, *, sync: bool = True) -> None:
    """Temp file + rename: readers see the old file or the new one, never a torn one."""
    tmp = path.with_name(f".{path.name}.tmp")
    with tmp.open("wb") as handle:
        handle.write(data)
        if sync:
            handle.flush()
            os.fsync(handle.fileno())
    os.replace(tmp, path)


def link_atomic(source: Path, path: Path) -> None:
    """``source``'s bytes at ``path``: a hard link when both are on one file system (no space used), else
    a copy; through a temp name and a rename, like ``write_atomic``."""
    tmp = path.with_name(f".{path.name}.tmp")
    tmp.unlink(missing_ok=True)
    try:
        os.link(source, tmp)
    except OSError:  # another file system, or one without hard links
        shutil.copyfile(source, tmp)
    os.replace(tmp, path)
