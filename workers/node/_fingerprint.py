"""The harness fingerprint: one digest of everything on a node that can change a verdict or an episode.

A hand-bumped version number goes stale the first time a change forgets to bump it; a digest of
the things themselves cannot. The fingerprint has two kinds of parts:

- the code: the worker code (episodes, evaluation, agents, prompts, observations), the page-side
  JavaScript, the lock of the editor bundle, and the versions of the packages that drive the
  browser, the model calls and OCR; the driver and every node compute these from their checkout;
- the environment a node renders in: the editor bundle actually installed and the Chromium
  version (``editor:`` and ``browser:`` parts), which only a node with browsers can tell.

The digest over both is part of every job's id, recorded per row and in the run manifest, so
results made by other code or another browser are never taken for one another; each part's own
digest is kept, so two fingerprints can say which files differ.
"""

from __future__ import annotations

import hashlib
import json
import subprocess
from functools import cache
from importlib.metadata import PackageNotFoundError, version
from pathlib import Path

from workers.contract import HarnessFingerprint, fingerprint
from workers.node._installation import (
    BUNDLE_FILE,
    BUNDLE_PACKAGE,
    OWN_FILES,
    REPO_DIR,
    default_chromium,
    default_gui_dir,
)

WORKERS_DIR = REPO_DIR / "workers"

EDITOR_LOCK_FILES = ("package.json", "package-lock.json", "bare/package.json", "bare/package-lock.json")
"""Which editor bundle ``npm ci`` installs, byte for byte."""

EPISODE_PACKAGES = ("playwright", "litellm", "rapidocr", "onnxruntime", "opencv-python-headless", "numpy")
"""Packages whose version can change what an agent sees or what a model call returns."""


def file_digest(path: Path) -> str:
    """The first 16 hex digits of the file's SHA-256, or "missing"."""
    try:
        return hashlib.sha256(path.read_bytes()).hexdigest()[:16]
    except OSError:
        return "missing"


def _package_version(name: str) -> str:
    try:
        return version(name)
    except PackageNotFoundError:
        return "absent"


def code_parts(workers_dir: Path, gui_dir: Path) -> dict[str, str]:
    """A checkout's parts: its worker code, page files and editor lock, and this environment's packages."""
    parts: dict[str, str] = {}
    for path in sorted(workers_dir.rglob("*.py")):
        parts[f"workers/{path.relative_to(workers_dir).as_posix()}"] = file_digest(path)
    for name in (*OWN_FILES, *EDITOR_LOCK_FILES):
        parts[f"scratch-gui/{name}"] = file_digest(gui_dir / name)
    for name in EPISODE_PACKAGES:
        parts[f"package:{name}"] = _package_version(name)
    return parts


def environment_parts(gui_dir: Path, chromium: Path) -> dict[str, str]:
    """What this machine renders with: the installed editor bundle (version and digest) and Chromium."""
    dist = gui_dir / "node_modules" / BUNDLE_PACKAGE
    try:
        bundle_version = json.loads((dist / "package.json").read_text(encoding="utf-8")).get("version", "?")
        editor = f"{bundle_version} {file_digest(dist / 'dist' / BUNDLE_FILE)}"
    except (OSError, ValueError):
        editor = "missing"
    try:
        done = subprocess.run([str(chromium), "--version"], capture_output=True, text=True, timeout=60, check=True)
        browser = " ".join(done.stdout.split()[:2]) or "unknown"
    except (OSError, subprocess.SubprocessError):
        browser = "missing"
    return {"editor:bundle": editor, "browser:chromium": browser}


@cache
def harness_fingerprint() -> HarnessFingerprint:
    """This process's harness, code and environment, computed once (nothing changes under a running sweep)."""
    gui_dir = default_gui_dir()
    return fingerprint({**code_parts(WORKERS_DIR, gui_dir), **environment_parts(gui_dir, default_chromium())})
