"""This node: where its editor and browser are installed, its harness fingerprint, how it describes itself."""

from workers.node._describe import describe_node
from workers.node._fingerprint import code_parts, environment_parts, harness_fingerprint
from workers.node._installation import (
    BUNDLE_FILE,
    BUNDLE_PACKAGE,
    OWN_FILES,
    REPO_DIR,
    default_chromium,
    default_gui_dir,
)

__all__ = [
    "BUNDLE_FILE",
    "BUNDLE_PACKAGE",
    "OWN_FILES",
    "REPO_DIR",
    "code_parts",
    "default_chromium",
    "default_gui_dir",
    "describe_node",
    "environment_parts",
    "harness_fingerprint",
]
