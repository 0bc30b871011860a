"""A node's copy of a warm browser cache, so that a new browser's first editors open as cheaply as later ones.

A browser compiles the 17 MB editor bundle at its first two editor openings: V8 writes its code cache for
a script on the script's second load and serves it from the third (measured here: 8.0 and 7.5 CPU-s, then
4-5). The first browser session on a node that has opened two editors leaves its HTTP cache and V8's code
cache here when it closes. Every later browser's profile starts as a copy, so its first opening already runs
the compiled bundle.

Sharing them changes no page: every script a page loads comes from one fixed origin at a URL that carries
its content's digest, and that origin answers only at the current digest (``_server``), so a cached copy is
always of the content its URL names; nothing from an editor origin is kept (``no-store``); and V8 checks each
code-cache entry against the script's source, its own version and its flags, and compiles afresh on a
mismatch. A template is written once, whole (made beside it, then renamed into place), and read by copying;
one that cannot be read or written costs only the compile it would have saved.
"""

from __future__ import annotations

import hashlib
import logging
import os
import shutil
import tempfile
from pathlib import Path

from workers.node import user_cache_dir

log = logging.getLogger(__name__)

CACHE_DIRS = ("Cache", "Code Cache")
"""A Chromium profile's HTTP cache and V8's code cache (under the profile's ``Default/``)."""

PROFILE = "Default"

TEMPLATE_ENV = "SCRATCHWORLD_BROWSER_CACHE"
"""A node setting: the folder the templates live in, or ``off`` for none."""

OPENINGS_TO_OFFER = 2
"""Editor openings after which a session's cache holds the bundle's code cache (written on its second load)."""

FORMAT = "1"
"""Changes when what a template holds changes, so that older templates are not taken for one."""


def default_templates_dir() -> Path | None:
    """``SCRATCHWORLD_BROWSER_CACHE``, or ``$XDG_CACHE_HOME/scratchworld_dist/browser-cache``; None when ``off``."""
    setting = os.environ.get(TEMPLATE_ENV)
    if setting == "off":
        return None
    if setting:
        return Path(setting)
    return user_cache_dir() / "scratchworld_dist" / "browser-cache"


def template_key(executable: Path, bundle_version: str) -> str:
    """One Chromium build's templates apart from another's (its code cache is no use to another V8), and one
    editor bundle's apart from another's: a template is written once, so one kept from an earlier bundle
    would have every later browser compile the new one at its first two openings again."""
    resolved = executable.resolve()
    stat = resolved.stat()
    identity = f"{FORMAT} {resolved} {stat.st_size} {stat.st_mtime_ns} {bundle_version}"
    return hashlib.sha256(identity.encode()).hexdigest()[:16]


class CacheTemplate:
    """The template for one Chromium build and editor bundle in ``directory``: seeds new profiles, and is
    offered used ones."""

    def __init__(self, directory: Path, executable: Path, bundle_version: str) -> None:
        self.path = directory / template_key(executable, bundle_version)

    @classmethod
    def for_node(cls, executable: Path, bundle_version: str) -> CacheTemplate | None:
        """The node's template for ``executable`` and the bundle at ``bundle_version`` (its content's digest),
        or None when templates are off."""
        directory = default_templates_dir()
        return None if directory is None else cls(directory, executable, bundle_version)

    @property
    def exists(self) -> bool:
        return self.path.is_dir()

    def seed(self, profile: Path) -> bool:
        """Copy the template into a new, empty ``profile`` directory; whether there was one to copy."""
        if not self.exists:
            return False
        target = profile / PROFILE
        try:
            for name in CACHE_DIRS:
                shutil.copytree(self.path / name, target / name)
        except OSError as exc:  # a half copy is no worse than none: entries are checked as they are read
            log.warning("could not start a browser from the cache template %s (%s)", self.path, exc)
            return False
        return True

    def offer(self, profile: Path) -> bool:
        """Keep a closed browser's caches as the template unless there is one; whether they were kept."""
        if self.exists or not all((profile / PROFILE / name).is_dir() for name in CACHE_DIRS):
            return False
        made: Path | None = None
        try:
            self.path.parent.mkdir(parents=True, exist_ok=True)
            made = Path(tempfile.mkdtemp(prefix=f".{self.path.name}-", dir=self.path.parent))
            for name in CACHE_DIRS:
                shutil.copytree(profile / PROFILE / name, made / name)
            made.rename(self.path)  # whole or not at all; another browser's may have come first
            made = None
        except OSError as exc:
            if not self.exists:
                log.warning("could not keep a browser cache template at %s (%s)", self.path, exc)
            return False
        finally:
            if made is not None:
                shutil.rmtree(made, ignore_errors=True)
        return True
