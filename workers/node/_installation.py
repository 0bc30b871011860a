"""Where this node's editor and browser are installed, as the fingerprint and the editor both need to know.

Kept free of Playwright so that the driver and ``describe_node`` can read it cheaply.
"""

from __future__ import annotations

import os
import re
from pathlib import Path

REPO_DIR = Path(__file__).resolve().parents[2]
"""The checkout this process runs from."""

BUNDLE_PACKAGE = "@scratch/scratch-gui-standalone"
BUNDLE_FILE = "scratch-gui-standalone.js"

_SCRIPT = re.compile(r'<script src="([^"]+)"></script>')


def _own_files() -> tuple[str, ...]:
    """``index.html`` and the scripts it loads but the bundle: one list, kept in the page itself."""
    page = REPO_DIR / "scratch-gui" / "index.html"
    scripts = _SCRIPT.findall(page.read_text(encoding="utf-8")) if page.is_file() else []
    return ("index.html", *(name for name in scripts if name != BUNDLE_FILE))


OWN_FILES = _own_files()
"""Files of ours that shadow the bundle's web root (paths relative to ``scratch-gui/``), in the
order ``index.html`` loads its scripts."""

DEFAULT_CHROMIUM = Path("/usr/bin/chromium")


def default_gui_dir() -> Path:
    """The repository's ``scratch-gui/`` folder, or ``SCRATCHWORLD_GUI_DIR`` when set."""
    override = os.environ.get("SCRATCHWORLD_GUI_DIR")
    return Path(override) if override else REPO_DIR / "scratch-gui"


def default_chromium() -> Path:
    """Debian's Chromium, or ``SCRATCHWORLD_CHROMIUM`` when set."""
    override = os.environ.get("SCRATCHWORLD_CHROMIUM")
    return Path(override) if override else DEFAULT_CHROMIUM
