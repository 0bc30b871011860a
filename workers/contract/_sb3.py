"""Checking that bytes are a Scratch 3 project of a sane size before a browser is spent on them.

The editor inflates every entry of an .sb3 into memory (JSZip) before it looks at any, so a
small archive can take a page, or a whole worker, down: a costume that inflates to 1.5 GB, a
project.json of 800 MB. Sizes are checked here, in the worker, before the bytes reach a page:
the file itself, each entry's declared size, and then each entry inflated for real, in bounded
chunks, from exactly the compressed bytes the editor would read, because declared sizes can lie.
"""

from __future__ import annotations

import io
import json
import struct
import zipfile
import zlib
from typing import Any

from pydantic import BaseModel, ConfigDict, Field

from workers.contract._errors import ProjectFormatError, ProjectTooLargeError

MIB = 1024 * 1024
_CHUNK = MIB
_LOCAL_HEADER = struct.Struct("<4s2B4HL2L2H")
"""Zip local file header: signature ... name length, extra length (30 bytes)."""


class ProjectLimits(BaseModel):
    """The largest project a worker loads; generous for real projects, fatal for archive bombs.

    Part of a job's identity: a project refused under one limit may be evaluated under another.
    """

    model_config = ConfigDict(frozen=True, extra="forbid")

    max_file_mb: float = Field(default=64, gt=0)
    """The .sb3 (or bare project.json) as stored."""

    max_json_mb: float = Field(default=32, gt=0)
    """project.json once inflated."""

    max_entry_mb: float = Field(default=64, gt=0)
    """Any one asset (costume, sound) once inflated."""

    max_total_mb: float = Field(default=256, gt=0)
    """All entries together once inflated."""

    max_entries: int = Field(default=10_000, gt=0)
    """Files in the archive."""


def _mb(size: float) -> str:
    return f"{size / MIB:.2f} MiB" if size < 1024 * MIB else f"{size / 1024 / MIB:.2f} GiB"


def _too_large(what: str, size: float, limit_mb: float, field: str, *, inflating: bool = False) -> ProjectTooLargeError:
    """The error for ``what``: its size, or (cut short while inflating) that it passed the limit."""
    found = "inflates past" if inflating else f"is {_mb(size)}, over"
    return ProjectTooLargeError(f"{what} {found} the limit of {limit_mb:g} MiB (project_limits.{field})")


def check_project(data: bytes, limits: ProjectLimits | None = None) -> dict[str, Any]:
    """The project.json of an .sb3 (or of bare project JSON, which the VM also accepts), checked.

    Raises ``ProjectTooLargeError`` for a project over ``limits`` and ``ProjectFormatError``
    saying what is wrong otherwise: not a zip, no project.json, bad JSON, sizes that lie.
    """
    limits = limits or ProjectLimits()
    if not data:
        raise ProjectFormatError("the project is empty (0 bytes)")
    if len(data) > limits.max_file_mb * MIB:
        raise _too_large("the project file", len(data), limits.max_file_mb, "max_file_mb")
    if data[:2] == b"PK":
        text = _checked_archive(data, limits)
    elif data.lstrip()[:1] == b"{":
        if len(data) > limits.max_json_mb * MIB:
            raise _too_large("project.json", len(data), limits.max_json_mb, "max_json_mb")
        text = data
    else:
        raise ProjectFormatError(f"not an .sb3 zip archive nor project JSON (starts with {data[:8]!r})")
    try:
        project = json.loads(text)
    except (UnicodeDecodeError, json.JSONDecodeError, RecursionError) as exc:
        raise ProjectFormatError(f"project.json is not valid JSON ({type(exc).__name__}: {exc})"[:500]) from exc
    if not isinstance(project, dict) or not isinstance(project.get("targets"), list):
        raise ProjectFormatError("project.json has no list of targets: not a Scratch 3 project")
    return project


def _checked_archive(data: bytes, limits: ProjectLimits) -> bytes:
    """The bytes of project.json, once every entry was inflated within the limits."""
    try:
        with zipfile.ZipFile(io.BytesIO(data)) as archive:
            entries = archive.infolist()
            if len(entries) > limits.max_entries:
                raise ProjectTooLargeError(
                    f"the archive has {len(entries)} files, over the limit of {limits.max_entries} "
                    "(project_limits.max_entries)"
                )
            names = [entry.filename for entry in entries]
            if "project.json" not in names:
                raise ProjectFormatError("the .sb3 archive has no project.json")
            _check_declared(entries, limits)
            total = 0
            project_json = b""
            for entry in entries:
                content = _inflate(data, entry, _entry_limit(entry, limits))
                total += len(content)
                if total > limits.max_total_mb * MIB:
                    raise _too_large("the archive", total, limits.max_total_mb, "max_total_mb", inflating=True)
                if entry.filename == "project.json":
                    project_json = content
            return project_json
    except (zipfile.BadZipFile, zlib.error, EOFError, OSError, ValueError, struct.error) as exc:
        raise ProjectFormatError(f"the .sb3 is not a readable zip archive ({exc})") from exc


def _entry_limit(entry: zipfile.ZipInfo, limits: ProjectLimits) -> tuple[str, float, str]:
    """What the entry is called in messages, its limit in MiB and the field that sets it."""
    if entry.filename == "project.json":
        return "project.json", limits.max_json_mb, "max_json_mb"
    return f"the entry {entry.filename[:120]!r}", limits.max_entry_mb, "max_entry_mb"


def _check_declared(entries: list[zipfile.ZipInfo], limits: ProjectLimits) -> None:
    """Refuse on the sizes the archive declares, before inflating anything."""
    total = 0
    for entry in entries:
        what, limit_mb, field = _entry_limit(entry, limits)
        if entry.file_size > limit_mb * MIB:
            raise _too_large(what, entry.file_size, limit_mb, field)
        total += entry.file_size
    if total > limits.max_total_mb * MIB:
        raise _too_large("the inflated archive", total, limits.max_total_mb, "max_total_mb")


def _inflate(data: bytes, entry: zipfile.ZipInfo, limit: tuple[str, float, str]) -> bytes:
    """The entry's content, inflated from its compressed bytes in bounded chunks.

    The compressed range is the one a browser's zip reader uses (local header offset plus the
    central directory's compressed size); inflating stops as soon as the output passes the
    limit, and content whose size or checksum differs from what the archive declares is refused.
    """
    what, limit_mb, field = limit
    cap = int(limit_mb * MIB)
    header = _LOCAL_HEADER.unpack_from(data, entry.header_offset)
    if header[0] != b"PK\x03\x04":
        raise ProjectFormatError(f"{what}: bad local file header")
    start = entry.header_offset + _LOCAL_HEADER.size + header[-2] + header[-1]
    compressed = memoryview(data)[start : start + entry.compress_size]
    if len(compressed) != entry.compress_size:
        raise ProjectFormatError(f"{what}: the archive is truncated")
    if entry.compress_type == zipfile.ZIP_STORED:
        content = bytes(compressed)
        if len(content) > cap:
            raise _too_large(what, len(content), limit_mb, field)
    elif entry.compress_type == zipfile.ZIP_DEFLATED:
        content = _inflate_capped(compressed, cap, what, limit_mb, field)
    else:
        raise ProjectFormatError(f"{what}: compression method {entry.compress_type} is not one the editor reads")
    if len(content) != entry.file_size or zlib.crc32(content) != entry.CRC:
        raise ProjectFormatError(f"{what}: its content does not match the size or checksum the archive declares")
    return content


def _inflate_capped(compressed: memoryview, cap: int, what: str, limit_mb: float, field: str) -> bytes:
    inflater = zlib.decompressobj(-zlib.MAX_WBITS)
    out = bytearray()
    for offset in range(0, len(compressed), _CHUNK):
        out += inflater.decompress(compressed[offset : offset + _CHUNK], cap + 1 - len(out))
        while inflater.unconsumed_tail and len(out) <= cap:
            out += inflater.decompress(inflater.unconsumed_tail, cap + 1 - len(out))
        if len(out) > cap:
            raise _too_large(what, len(out), limit_mb, field, inflating=True)
    out += inflater.flush(cap + 1 - len(out))
    if len(out) > cap:
        raise _too_large(what, len(out), limit_mb, field, inflating=True)
    return bytes(out)
