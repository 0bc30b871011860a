"""The driver's local mirror of a remote run directory: where it is, and how it is brought level with the bucket.

The driver writes a remote run on local disk first (commits stay atomic and fast) and the uploader copies it up.
When a run starts, the mirror is trusted only if it was written by the session that wrote the bucket last (the
lease names it): then whatever it holds that the bucket lacks (uploads cut short by a crash or an outage) is
pushed. Otherwise (an empty folder on another machine, or a mirror another driver has overtaken) it is rebuilt
from the bucket: the manifest, the events, the compacted shards and the journal entries of segments not yet
compacted, the memory a sweep keeps; never the artifacts, which stay in the bucket.
"""

from __future__ import annotations

import json
import re
import shutil
from pathlib import Path
from typing import TYPE_CHECKING

from scratchworld_dist._errors import RunDirError
from scratchworld_dist._files import write_atomic
from scratchworld_dist.results.remote._location import RemoteLocation
from workers.node import user_cache_dir

if TYPE_CHECKING:
    from fsspec import AbstractFileSystem

    from scratchworld_dist.results.remote._uploader import Uploader

MIRROR_MARK = ".remote.json"
"""In a mirror: the URL it mirrors and the lease token of the session that last wrote from it."""

_LOCAL_ONLY = {MIRROR_MARK, ".lock"}
_PART = re.compile(r"^([a-z_]+)/part-(\d{6})\.parquet$")
_ENTRY = re.compile(r"^journal/segment-(\d{6})/(\d{6})\.json$")
_PULLED = re.compile(r"^(manifest\.json|events\.jsonl|memory/.+)$")


def default_mirror(location: RemoteLocation, cache_dir: Path | None) -> Path:
    """``cache_dir`` (default ``$XDG_CACHE_HOME/scratchworld/runs``, else ``~/.cache/...``)/protocol/bucket/prefix."""
    base = cache_dir or user_cache_dir() / "scratchworld" / "runs"
    return base / location.protocol / location.root.lstrip("/")


def entry_key(segment: int, line: int) -> str:
    """A committed attempt's journal entry in the bucket (one object per attempt)."""
    return f"journal/segment-{segment:06d}/{line:06d}.json"


def segment_folder(segment: int) -> str:
    return f"journal/segment-{segment:06d}"


def mirror_token(folder: Path) -> str | None:
    """The lease token of the session that last wrote from ``folder`` (None: it is no mirror yet)."""
    try:
        return json.loads((folder / MIRROR_MARK).read_text())["token"]
    except (OSError, ValueError, KeyError, TypeError):
        return None


def mark_mirror(folder: Path, location: RemoteLocation, token: str) -> None:
    write_atomic(folder / MIRROR_MARK, json.dumps({"url": location.url, "token": token}).encode(), sync=False)


def check_mirror(folder: Path, location: RemoteLocation) -> None:
    """Refuse a folder that holds something other than this run's mirror (it would be wiped by a pull)."""
    if not folder.exists():
        return
    if not folder.is_dir():
        raise RunDirError(f"{folder}: the local mirror of {location.url} is a file; choose another storage.cache_dir")
    if any(folder.iterdir()) and not (folder / MIRROR_MARK).is_file():
        raise RunDirError(
            f"{folder}: not empty and not a mirror of {location.url} (no {MIRROR_MARK}); "
            "choose another storage.cache_dir"
        )


def remote_files(fs: AbstractFileSystem, location: RemoteLocation) -> list[str]:
    """Every file of the run in the bucket, relative to its root."""
    fs.invalidate_cache()
    try:
        found = fs.find(location.root)
    except FileNotFoundError:
        return []
    prefix = location.root.rstrip("/") + "/"
    return sorted(path[len(prefix) :] for path in found if path.startswith(prefix))


def pull(fs: AbstractFileSystem, location: RemoteLocation, folder: Path) -> int:
    """Rebuild ``folder`` from the bucket (everything a driver needs to resume, no artifacts); the number of
    committed attempts found in journal entries of segments not yet compacted."""
    if folder.exists():
        shutil.rmtree(folder)
    folder.mkdir(parents=True)
    files = remote_files(fs, location)
    done = {int(m.group(2)) for f in files if (m := _PART.match(f)) and m.group(1) == "jobs"}
    entries: dict[int, list[tuple[int, str]]] = {}
    for relative in files:
        part, entry = _PART.match(relative), _ENTRY.match(relative)
        if (part is not None and int(part.group(2)) in done) or _PULLED.match(relative):
            _download(fs, location, relative, folder)
        elif entry is not None and int(entry.group(1)) not in done:
            entries.setdefault(int(entry.group(1)), []).append((int(entry.group(2)), relative))
    write_segments(fs, location, entries, folder / "journal")
    return sum(len(lines) for lines in entries.values())


def write_segments(
    fs: AbstractFileSystem, location: RemoteLocation, entries: dict[int, list[tuple[int, str]]], journal: Path
) -> None:
    """Local journal segments made of the bucket's entries (each segment's in line order)."""
    journal.mkdir(parents=True, exist_ok=True)
    for segment, lines in sorted(entries.items()):
        keys = [location.key(relative) for _, relative in sorted(lines)]
        blobs = fs.cat(keys)
        data = b"".join(blobs[key].rstrip(b"\n") + b"\n" for key in keys)
        write_atomic(journal / f"segment-{segment:06d}.jsonl", data, sync=False)


def push_missing(fs: AbstractFileSystem, location: RemoteLocation, folder: Path, uploader: Uploader) -> int:
    """Hand the uploader every file of the mirror the bucket lacks (shards before their ``jobs`` shard, the
    manifest and events always, last), then the deletion of journal entries whose segment is compacted; the
    number of files handed over."""
    remote = set(remote_files(fs, location))
    local = sorted(
        str(path.relative_to(folder))
        for path in folder.rglob("*")
        if path.is_file() and not path.name.startswith(".") and path.relative_to(folder).parts[0] != "journal"
    )
    late = {"manifest.json", "events.jsonl"}
    missing = [f for f in local if f not in remote and f not in late and f not in _LOCAL_ONLY]
    missing.sort(key=lambda f: f.startswith("jobs/"))  # stable: each table's parts in order, jobs after all
    for relative in [*missing, *(f for f in local if f in late)]:
        uploader.put_file(location.key(relative), folder / relative)
    compacted = {int(m.group(2)) for f in local if (m := _PART.match(f)) and m.group(1) == "jobs"}
    for segment in sorted({int(m.group(1)) for f in remote if (m := _ENTRY.match(f))} & compacted):
        uploader.delete_folder(location.key(segment_folder(segment)))
    return len(missing)


def _download(fs: AbstractFileSystem, location: RemoteLocation, relative: str, folder: Path) -> None:
    target = folder / relative
    target.parent.mkdir(parents=True, exist_ok=True)
    write_atomic(target, fs.cat_file(location.key(relative)), sync=False)
