"""The viewer as static files: every page, the package's stylesheet and script, the artifacts pages show.

The copy links only to itself by relative paths, so it opens from ``file://`` or any static server,
with no network access (nothing is fetched from elsewhere).
"""

from __future__ import annotations

from pathlib import Path

from pydantic import BaseModel

from scratchworld_dist._errors import RunDirError
from scratchworld_dist._files import link_atomic
from scratchworld_dist.viewer._site import ViewerSite


class ExportSummary(BaseModel):
    out: Path
    pages: int
    files: int
    bytes: int


def export_site(site: ViewerSite, out: Path) -> ExportSummary:
    """Write the site to ``out`` (created; an existing folder must be empty or an earlier export)."""
    if out.exists() and not out.is_dir():
        raise RunDirError(f"{out}: exists and is not a folder")
    if out.is_dir() and any(out.iterdir()) and not (out / "index.html").is_file():
        raise RunDirError(f"{out}: not empty and not an earlier export; choose an empty folder")
    for run in site.runs:
        if out.resolve().is_relative_to(run.path.resolve()):
            raise RunDirError(f"{out}: inside run directory {run.path}; export elsewhere")
    out.mkdir(parents=True, exist_ok=True)
    pages = files = size = 0
    for path in site.page_paths():
        resource = site.get(path)
        if resource is None or resource.body is None:
            continue
        target = out / path
        target.parent.mkdir(parents=True, exist_ok=True)
        target.write_bytes(resource.body)
        pages += 1
        size += len(resource.body)
    for path, source in site.artifact_files():
        target = out / path
        target.parent.mkdir(parents=True, exist_ok=True)
        link_atomic(source, target)
        files += 1
        size += source.stat().st_size
    return ExportSummary(out=out, pages=pages, files=files, bytes=size)
