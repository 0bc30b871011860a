"""The editor in a browser: Chromium per worker, the served editor files, one editor page, a pool of them,
what one editor costs the node, and a page's screencast."""

from workers.editor._browser import BrowserConfig, BrowserSession
from workers.editor._cost import cached_editor_cost, measure_editor_cost
from workers.editor._editor import Editor, EditorStatus, StageLayout, opened
from workers.editor._pool import EditorPool
from workers.editor._screencast import FrameSink, Screencast, ScreencastFrame
from workers.editor._server import EditorAssets, EditorServer
from workers.editor._switches import CHROMIUM_ARGS, isolation_args

__all__ = [
    "CHROMIUM_ARGS",
    "BrowserConfig",
    "BrowserSession",
    "Editor",
    "EditorAssets",
    "EditorPool",
    "EditorServer",
    "EditorStatus",
    "FrameSink",
    "Screencast",
    "ScreencastFrame",
    "StageLayout",
    "cached_editor_cost",
    "isolation_args",
    "measure_editor_cost",
    "opened",
]
