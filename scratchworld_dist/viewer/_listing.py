"""A final project's scripts as indented text, read from its project.json (no editor needed).

The listing itself is ``scratchworld_dist.sb3.target_listing``; this reads it out of an .sb3 that may be
anything an agent left (not a zip, no project.json, too large).
"""

from __future__ import annotations

import io
import json
import zipfile

from scratchworld_dist.sb3 import target_listing

MAX_PROJECT_JSON = 32 * 2**20
"""The largest project.json listed; a bigger one is named, not read."""


def project_listing(sb3: bytes) -> str:
    """Every target's scripts, or one line saying why the project cannot be listed."""
    try:
        with zipfile.ZipFile(io.BytesIO(sb3)) as archive:
            info = archive.getinfo("project.json")
            if info.file_size > MAX_PROJECT_JSON:
                return f"project.json is {info.file_size} bytes: too large to list"
            project = json.loads(archive.read(info))
    except (zipfile.BadZipFile, KeyError, ValueError, OSError) as exc:
        return f"not a readable Scratch 3 project: {exc}"
    if not isinstance(project, dict) or not isinstance(project.get("targets"), list):
        return "not a Scratch 3 project: project.json has no targets"
    parts = [target_listing(t) for t in project["targets"] if isinstance(t, dict)]
    return "\n\n".join(parts) or "no targets"
