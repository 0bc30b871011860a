"""This node: where its editor and browser are installed, its harness fingerprint, how it describes itself,
what its browsers cost and how many episodes it can hold."""

from workers.node._capacity import (
    DELIVERED_PER_CORE,
    PRIMITIVE_DELIVERED_PER_CORE,
    EditorCost,
    SlotDerivation,
    delivered_per_core,
    derive_slots,
)
from workers.node._describe import describe_node
from workers.node._fingerprint import code_parts, environment_parts, file_digest, harness_fingerprint
from workers.node._installation import (
    BARE_BUILT_FILES,
    BARE_DIR,
    BARE_PAGE,
    BARE_VENDOR_PACKAGES,
    BARE_VENDOR_URL,
    BUNDLE_FILE,
    BUNDLE_PACKAGE,
    EDITOR_PAGE,
    OWN_FILES,
    PAGES,
    REPO_DIR,
    default_chromium,
    default_gui_dir,
    user_cache_dir,
)
from workers.node._priority import idle_priority, thread_policies
from workers.node._usage import BrowserUsage, NodeMemory, browser_usage, node_memory

__all__ = [
    "BARE_BUILT_FILES",
    "BARE_DIR",
    "BARE_PAGE",
    "BARE_VENDOR_PACKAGES",
    "BARE_VENDOR_URL",
    "BUNDLE_FILE",
    "BUNDLE_PACKAGE",
    "DELIVERED_PER_CORE",
    "EDITOR_PAGE",
    "OWN_FILES",
    "PAGES",
    "PRIMITIVE_DELIVERED_PER_CORE",
    "REPO_DIR",
    "BrowserUsage",
    "EditorCost",
    "NodeMemory",
    "SlotDerivation",
    "browser_usage",
    "code_parts",
    "default_chromium",
    "default_gui_dir",
    "delivered_per_core",
    "derive_slots",
    "describe_node",
    "environment_parts",
    "file_digest",
    "harness_fingerprint",
    "idle_priority",
    "node_memory",
    "thread_policies",
    "user_cache_dir",
]
