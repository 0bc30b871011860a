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
"""The editor bundle, as ``install.sh`` leaves it: re-encoded to ASCII and its languages but English built on
first use (a waiting editor's memory; see there)."""

EDITOR_PAGE = "index.html"
"""The Scratch editor (agents' episodes; the reference page for evaluations)."""
BARE_PAGE = "bare.html"
"""The evaluation page without the editor GUI (``scratch-gui/bare/``)."""
PAGES = (EDITOR_PAGE, BARE_PAGE)

BARE_DIR = "bare"
"""The bare page's own npm install (``bare/package.json``) and what ``install.sh`` builds from it."""
BARE_VENDOR_URL = "bare/vendor/"
"""Where the bare page loads npm packages' browser builds: ``bare/vendor/<name>/<file>`` is
``bare/node_modules/@scratch/<name>/dist/web/<file>``."""
BARE_VENDOR_PACKAGES = ("scratch-vm", "scratch-render", "scratch-storage", "scratch-svg-renderer")
BARE_BUILT_FILES = ("bare/build/scratch-audio.js",)
"""Files ``install.sh`` builds (scratch-audio is CommonJS; esbuild makes it one browser script)."""

_SCRIPT = re.compile(r'<script src="([^"]+)"></script>')


def _own_files() -> tuple[str, ...]:
    """The two pages and the scripts they load but installed packages: one list, kept in the pages."""
    files: list[str] = []
    installed = (BUNDLE_FILE, *BARE_BUILT_FILES)
    for name in PAGES:
        page = REPO_DIR / "scratch-gui" / name
        scripts = _SCRIPT.findall(page.read_text(encoding="utf-8")) if page.is_file() else []
        mine = [s for s in scripts if s not in installed and not s.startswith(BARE_VENDOR_URL)]
        files += [f for f in (name, *mine) if f not in files]
    return tuple(files)


OWN_FILES = _own_files()
"""Files of ours that shadow the bundle's web root (paths relative to ``scratch-gui/``): each page,
then the scripts it loads in order."""

DEFAULT_CHROMIUM = Path("/usr/bin/chromium")


def default_gui_dir() -> Path:
    """The repository's ``scratch-gui/`` folder, or ``SCRATCHWORLD_GUI_DIR`` when set."""
    override = os.environ.get("SCRATCHWORLD_GUI_DIR")
    return Path(override) if override else REPO_DIR / "scratch-gui"


def user_cache_dir() -> Path:
    """The user's cache folder (``$XDG_CACHE_HOME``, else ``~/.cache``), where this node keeps what it can rebuild."""
    return Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache")


def default_chromium() -> Path:
    """Debian's Chromium, or ``SCRATCHWORLD_CHROMIUM`` when set."""
    override = os.environ.get("SCRATCHWORLD_CHROMIUM")
    return Path(override) if override else DEFAULT_CHROMIUM
