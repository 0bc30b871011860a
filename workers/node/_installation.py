"""Where this node's editor and browser are installed, as the fingerprint and the editor both need to know.

Kept free of Playwright so that the driver and ``describe_node`` can read it cheaply.
"""

from __future__ import annotations

import os
from pathlib import Path

REPO_DIR = Path(__file__).resolve().parents[2]
"""The checkout this process runs from."""

BUNDLE_PACKAGE = "@scratch/scratch-gui-standalone"
BUNDLE_FILE = "scratch-gui-standalone.js"

OWN_FILES = (
    "index.html",
    "clock.js",
    "recycle.js",
    "recycle-gui.js",
    "modules.js",
    "shared/rects.js",
    "shared/blockly.js",
    "shared/settle.js",
    "composite/arguments.js",
    "composite/target.js",
    "composite/catalog.js",
    "composite/numbering.js",
    "composite/observation.js",
    "composite/structure.js",
    "composite/connect.js",
    "composite/fields.js",
    "composite/edit.js",
    "composite/execute.js",
    "primitive/elements.js",
    "geometry/views.js",
    "geometry/blocks.js",
    "geometry/widgets.js",
    "geometry/drag-plan.js",
    "geometry/snapshot.js",
    "geometry/waits.js",
    "bridge.js",
)
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
