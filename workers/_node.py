"""What a node says about itself before it gets jobs: where it is, which harness it runs, how many editors it holds.

The driver asks every node with browser slots (a Ray task pinned to each) and refuses to run
when one runs other code or renders with another editor or browser, naming it: otherwise that
node would produce verdicts under job ids that name a harness it does not run.
"""

from __future__ import annotations

import os
import socket

from pydantic import BaseModel, ConfigDict

from workers._fingerprint import REPO_DIR, HarnessFingerprint, harness_fingerprint


class NodeReport(BaseModel):
    """One node as it describes itself (computed on the node, from its own checkout and installation)."""

    model_config = ConfigDict(frozen=True)

    node_id: str
    hostname: str
    address: str
    """The node's IP address as Ray knows it."""

    harness_dir: str
    """The checkout this node's workers run from."""

    harness: HarnessFingerprint
    browser_slots: int = 0

    @property
    def name(self) -> str:
        """How messages name the node: host, address, Ray node id and checkout."""
        return f"{self.hostname} ({self.address}, node {self.node_id[:8]}, harness at {self.harness_dir})"

    def summary(self) -> NodeSummary:
        return NodeSummary(
            node_id=self.node_id,
            hostname=self.hostname,
            address=self.address,
            harness_dir=self.harness_dir,
            harness=self.harness.digest,
            editor=self.harness.parts.get("editor:bundle", "?"),
            browser=self.harness.parts.get("browser:chromium", "?"),
            browser_slots=self.browser_slots,
        )


class NodeSummary(BaseModel):
    """A node as the run manifest records it."""

    node_id: str
    hostname: str
    address: str
    harness_dir: str
    harness: str
    editor: str
    browser: str
    browser_slots: int


def describe_node(node_id: str = "local", address: str | None = None, browser_slots: int = 0) -> NodeReport:
    """This machine as a node: runs on the node it describes (a pinned Ray task, or the driver itself)."""
    hostname = socket.gethostname()
    return NodeReport(
        node_id=node_id,
        hostname=hostname,
        address=address or os.environ.get("RAY_NODE_IP_ADDRESS", "127.0.0.1"),
        harness_dir=str(REPO_DIR),
        harness=harness_fingerprint(),
        browser_slots=browser_slots,
    )
