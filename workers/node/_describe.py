"""What a node says about itself before it gets jobs: where it is, which harness it runs, how many editors it holds.

The driver asks every node with browser slots (a Ray task pinned to each) and refuses to run
when one runs other code or renders with another editor or browser, naming it: otherwise that
node would produce verdicts under job ids that name a harness it does not run.
"""

from __future__ import annotations

import os
import socket

from workers.contract import NodeReport
from workers.node._fingerprint import harness_fingerprint
from workers.node._installation import REPO_DIR


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
