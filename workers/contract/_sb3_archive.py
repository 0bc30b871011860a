"""A project's files with project.json swapped out: variants of one project (a connection cut, a script
moved, a grader audit's mutant) written without unpacking and repacking its assets for each; shared by the
driver, which makes variants, and the workers, which rebuild an audit's variant from its golden."""

from __future__ import annotations

import io
import json
import zipfile
from collections.abc import Mapping
from typing import Any


class Sb3Archive:
    """The project's files but project.json, zipped once; ``with_project`` appends a project.json to a copy.

    A project given as bare JSON (no zip) stays bare JSON. Entries carry a fixed timestamp, so the same
    project.json gives the same bytes.
    """

    def __init__(self, data: bytes) -> None:
        self.zipped = data[:2] == b"PK"
        buffer = io.BytesIO()
        if self.zipped:
            with zipfile.ZipFile(io.BytesIO(data)) as source, zipfile.ZipFile(buffer, "w") as out:
                for info in source.infolist():
                    if info.filename != "project.json" and not info.is_dir():
                        out.writestr(_entry(info.filename), source.read(info))
        self.base = buffer.getvalue()

    def with_project(self, project: Mapping[str, Any]) -> bytes:
        text = json.dumps(project, separators=(",", ":")).encode("utf-8")
        if not self.zipped:
            return text
        buffer = io.BytesIO(self.base)
        with zipfile.ZipFile(buffer, "a") as out:
            out.writestr(_entry("project.json"), text)
        return buffer.getvalue()


def _entry(name: str) -> zipfile.ZipInfo:
    info = zipfile.ZipInfo(name, date_time=(1980, 1, 1, 0, 0, 0))
    info.compress_type = zipfile.ZIP_DEFLATED
    return info
