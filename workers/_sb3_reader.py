"""Checking that bytes are a Scratch 3 project before a browser is spent on them."""

from __future__ import annotations

import io
import json
import zipfile
from typing import Any

from workers._errors import ProjectFormatError


def read_project_json(data: bytes) -> dict[str, Any]:
    """The project.json of an .sb3 (or of bare project JSON, which the VM also accepts).

    Raises ``ProjectFormatError`` saying what is wrong: not a zip, no project.json, bad JSON.
    """
    if not data:
        raise ProjectFormatError("the project is empty (0 bytes)")
    if data[:2] == b"PK":
        try:
            with zipfile.ZipFile(io.BytesIO(data)) as archive:
                if "project.json" not in archive.namelist():
                    raise ProjectFormatError("the .sb3 archive has no project.json")
                text = archive.read("project.json")
        except (zipfile.BadZipFile, EOFError, OSError, ValueError) as exc:
            if isinstance(exc, ProjectFormatError):
                raise
            raise ProjectFormatError(f"the .sb3 is not a readable zip archive ({exc})") from exc
    elif data.lstrip()[:1] == b"{":
        text = data
    else:
        raise ProjectFormatError(f"not an .sb3 zip archive nor project JSON (starts with {data[:8]!r})")
    try:
        project = json.loads(text)
    except (UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise ProjectFormatError(f"project.json is not valid JSON ({exc})") from exc
    if not isinstance(project, dict) or not isinstance(project.get("targets"), list):
        raise ProjectFormatError("project.json has no list of targets: not a Scratch 3 project")
    return project
