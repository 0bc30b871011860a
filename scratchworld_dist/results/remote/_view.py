"""A remote run directory read in place, through a small local view.

Readers of a run (``report``, ``status``, ``export``, ``view``, ``compare``, ``regrade``, ``api.load_results``) take
a folder. For ``s3://bucket/run`` they get a view folder holding only the run's small files (the manifest, the
events, the journal entries not yet compacted, as a local segment) and a mark naming the URL. The run store reads
the Parquet shards from the bucket itself (pyarrow over the fsspec filesystem, column by column); an artifact (a
trajectory, a screenshot, a final project) is fetched into the view when a reader opens it, never before.
"""

from __future__ import annotations

import hashlib
import json
import re
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

from scratchworld_dist._errors import NotARunDirError, RunDirError
from scratchworld_dist._files import write_atomic
from scratchworld_dist.results.remote._location import RemoteLocation, parse_location
from scratchworld_dist.results.remote._mirror import remote_files, write_segments
from workers.node import user_cache_dir

if TYPE_CHECKING:
    from fsspec import AbstractFileSystem

VIEW_MARK = ".remote-view.json"
_PART = re.compile(r"^([a-z_]+)/part-(\d{6})\.parquet$")
_ENTRY = re.compile(r"^journal/segment-(\d{6})/(\d{6})\.json$")
_SMALL = ("manifest.json", "events.jsonl")


@dataclass
class RemoteView:
    """A view folder's remote run: its location and filesystem, and the files listed when the view was made."""

    location: RemoteLocation
    fs: AbstractFileSystem
    folder: Path

    def parts(self, table: str) -> dict[int, str]:
        """The table's shards in the bucket now, by segment number (fsspec paths)."""
        self.fs.invalidate_cache()
        try:
            names = self.fs.ls(self.location.key(table), detail=False)
        except FileNotFoundError:
            return {}
        found: dict[int, str] = {}
        prefix = self.location.root.rstrip("/") + "/"
        for name in names:
            match = _PART.match(str(name).removeprefix(prefix))
            if match is not None and match.group(1) == table:
                found[int(match.group(2))] = str(name)
        return found

    def fetch(self, relative: str) -> Path:
        """The local copy of one file of the run, fetched now if the view lacks it (it may not exist remotely)."""
        target = self.folder / relative
        if not target.is_file() and _inside(self.folder, target):
            try:
                data = self.fs.cat_file(self.location.key(relative))
            except (FileNotFoundError, IsADirectoryError):
                return target
            target.parent.mkdir(parents=True, exist_ok=True)
            write_atomic(target, data, sync=False)
        return target

    def fetch_folder(self, relative: str) -> Path:
        """The local copy of a folder of the run (an attempt's artifacts), fetched whole the first time."""
        target = self.folder / relative
        done = target / ".fetched"
        if not done.is_file() and _inside(self.folder, target):
            self.fs.invalidate_cache()
            prefix = self.location.key(relative).rstrip("/") + "/"
            try:
                keys = [k for k in self.fs.find(prefix) if k.startswith(prefix)]
            except FileNotFoundError:
                keys = []
            for key, data in (self.fs.cat(keys) if keys else {}).items():
                path = target / key[len(prefix) :]
                path.parent.mkdir(parents=True, exist_ok=True)
                write_atomic(path, data, sync=False)
            if keys:
                done.write_bytes(b"")
        return target


def _inside(folder: Path, target: Path) -> bool:
    return target.resolve().is_relative_to(folder.resolve())


_VIEWS: dict[Path, RemoteView] = {}


def view_of(run_dir: Path) -> RemoteView | None:
    """The remote run ``run_dir`` is a view of (None: a local run directory)."""
    key = run_dir.absolute()
    if key in _VIEWS:
        return _VIEWS[key]
    mark = run_dir / VIEW_MARK
    if not mark.is_file():
        return None
    try:
        location = parse_location(json.loads(mark.read_text())["url"])
    except (OSError, ValueError, KeyError, TypeError) as exc:
        raise RunDirError(f"{mark}: unreadable view mark ({exc})") from None
    view = RemoteView(location, location.filesystem(), run_dir)
    _VIEWS[key] = view
    return view


def local_file(run_dir: Path, relative: str) -> Path:
    """``run_dir / relative``, fetched first when ``run_dir`` is a view of a remote run."""
    view = view_of(run_dir)
    return view.fetch(relative) if view is not None else run_dir / relative


def local_folder(run_dir: Path, relative: str) -> Path:
    """``run_dir / relative`` (a folder), fetched whole first when ``run_dir`` is a view of a remote run."""
    view = view_of(run_dir)
    return view.fetch_folder(relative) if view is not None else run_dir / relative


def views_dir() -> Path:
    return user_cache_dir() / "scratchworld" / "views"


def open_view(url: str) -> Path:
    """A fresh view folder of the run at ``url``: its manifest, events and uncompacted journal entries fetched
    (artifacts and shards stay in the bucket); ``NotARunDirError`` when no run is there."""
    location = parse_location(url)
    fs = location.filesystem()
    folder = views_dir() / hashlib.sha256(location.url.encode()).hexdigest()[:16]
    try:
        files = remote_files(fs, location)
    except Exception as exc:
        raise RunDirError(f"{location.url}: cannot read the run: {' '.join(str(exc).split())[:200]}") from None
    if "manifest.json" not in files:
        raise NotARunDirError(location.url, "no such run in the bucket" if not files else "no manifest.json in it")
    folder.mkdir(parents=True, exist_ok=True)  # artifacts fetched before stay (objects never change)
    for stale in (folder / "journal").glob("*.jsonl"):
        stale.unlink(missing_ok=True)
    for name in _SMALL:
        if name in files:
            write_atomic(folder / name, fs.cat_file(location.key(name)), sync=False)
    done = {int(m.group(2)) for f in files if (m := _PART.match(f)) and m.group(1) == "jobs"}
    entries: dict[int, list[tuple[int, str]]] = {}
    for relative in files:
        match = _ENTRY.match(relative)
        if match is not None and int(match.group(1)) not in done:
            entries.setdefault(int(match.group(1)), []).append((int(match.group(2)), relative))
    write_segments(fs, location, entries, folder / "journal")
    write_atomic(folder / VIEW_MARK, json.dumps({"url": location.url}).encode(), sync=False)
    _VIEWS.pop(folder.absolute(), None)
    return folder


def shown_location(run_dir: Path) -> str:
    """How a run directory is named to the user: the URL of a remote run's view, else its path."""
    view = view_of(run_dir)
    return view.location.url if view is not None else str(run_dir)
