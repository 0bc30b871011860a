"""The harness fingerprint: one digest of everything on a node that can change a verdict or an episode.

A hand-bumped version number goes stale the first time a change forgets to bump it; a digest of
the files themselves cannot. The fingerprint covers the worker code (episodes, evaluation,
agents, prompts, observations), the page-side JavaScript, the lock of the editor bundle, and the
versions of the packages that drive the browser, the model calls and OCR. It is part of every
job's id, recorded per row and in the run manifest, and each node of a cluster reports its own,
so results made by different code are never taken for one another.

The digest of each part is kept, so two fingerprints can say which files differ.
"""

from __future__ import annotations

import hashlib
import json
from functools import cache
from importlib.metadata import PackageNotFoundError, version
from pathlib import Path

from pydantic import BaseModel, ConfigDict

from workers._editor_server import OWN_FILES, default_gui_dir

WORKERS_DIR = Path(__file__).resolve().parent
REPO_DIR = WORKERS_DIR.parent

EPISODE_CODE_OUTSIDE_WORKERS = ("scratchworld_dist/scheduling/_worker_actor.py",)
"""Driver-side modules that run inside a worker process (the actor that runs episodes)."""

EDITOR_LOCK_FILES = ("package.json", "package-lock.json")
"""Which editor bundle ``npm ci`` installs, byte for byte."""

EPISODE_PACKAGES = ("playwright", "litellm", "rapidocr", "onnxruntime", "opencv-python-headless", "numpy")
"""Packages whose version can change what an agent sees or what a model call returns."""


class HarnessFingerprint(BaseModel):
    """A digest over named parts (files by path, packages by ``package:<name>``), and the parts."""

    model_config = ConfigDict(frozen=True)

    digest: str
    """16 hex digits over every part; what job ids and rows carry."""

    parts: dict[str, str]
    """Each part's own digest (files) or version (packages), for saying what differs."""

    def differences(self, other: HarnessFingerprint) -> list[str]:
        """The parts that differ between two fingerprints, each once, in order."""
        names = sorted(set(self.parts) | set(other.parts))
        return [name for name in names if self.parts.get(name) != other.parts.get(name)]


def describe_differences(ours: HarnessFingerprint, theirs: HarnessFingerprint, limit: int = 8) -> str:
    """``workers/_editor.py, package:litellm (+3 more)``: the first few differing parts."""
    differing = ours.differences(theirs)
    shown = ", ".join(differing[:limit])
    return shown + (f" (+{len(differing) - limit} more)" if len(differing) > limit else "")


def _file_digest(path: Path) -> str:
    try:
        return hashlib.sha256(path.read_bytes()).hexdigest()[:16]
    except OSError:
        return "missing"


def _package_version(name: str) -> str:
    try:
        return version(name)
    except PackageNotFoundError:
        return "absent"


def fingerprint_of(workers_dir: Path, repo_dir: Path, gui_dir: Path) -> HarnessFingerprint:
    """The fingerprint of a checkout: its worker code, page files and editor lock, and this environment's packages."""
    parts: dict[str, str] = {}
    for path in sorted(workers_dir.rglob("*.py")):
        parts[f"workers/{path.relative_to(workers_dir).as_posix()}"] = _file_digest(path)
    for name in EPISODE_CODE_OUTSIDE_WORKERS:
        parts[name] = _file_digest(repo_dir / name)
    for name in (*OWN_FILES, *EDITOR_LOCK_FILES):
        parts[f"scratch-gui/{name}"] = _file_digest(gui_dir / name)
    for name in EPISODE_PACKAGES:
        parts[f"package:{name}"] = _package_version(name)
    canonical = json.dumps(parts, sort_keys=True, separators=(",", ":")).encode()
    return HarnessFingerprint(digest=hashlib.sha256(canonical).hexdigest()[:16], parts=parts)


@cache
def harness_fingerprint() -> HarnessFingerprint:
    """This process's harness, computed once (the files do not change under a running sweep)."""
    return fingerprint_of(WORKERS_DIR, REPO_DIR, default_gui_dir())
