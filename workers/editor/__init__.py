"""The editor in a browser: Chromium per worker, the served editor files, one editor page, a pool of them."""

from workers.editor._browser import CHROMIUM_ARGS, BrowserConfig, BrowserSession, isolation_args
from workers.editor._editor import Editor, EditorStatus, StageLayout, opened
from workers.editor._pool import EditorPool
from workers.editor._server import EditorAssets, EditorServer

__all__ = [
    "CHROMIUM_ARGS",
    "BrowserConfig",
    "BrowserSession",
    "Editor",
    "EditorAssets",
    "EditorPool",
    "EditorServer",
    "EditorStatus",
    "StageLayout",
    "isolation_args",
    "opened",
]
