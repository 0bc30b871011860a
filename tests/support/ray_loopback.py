"""`ray start` for the clusters that tests and benchmarks start on this machine: every node on 127.0.0.1 only.

Ray binds its servers to loopback only when a node's address is 127.0.0.1. ``ray start`` swaps 127.0.0.1
(whether given by ``--node-ip-address`` or found in ``--address``) for this machine's network address unless
Ray's cluster mode is off (``RAY_ENABLE_WINDOWS_OR_OSX_CLUSTER=0``), and with it off it refuses to start any
node but a head. So nodes are started by Ray's own CLI with that one swap left out (Ray 2.60:
``ray._private.services.resolve_ip_for_localhost``), and given ``--node-ip-address=127.0.0.1``; their
processes then listen on loopback only, which ``tests/scratchworld_dist/scheduling/test_ray_loopback.py``
checks socket by socket.
Users' clusters are started with plain ``ray start`` (docs/cluster.md).
"""

from __future__ import annotations

import sys

LOOPBACK = "127.0.0.1"

_RAY_CLI_KEEPING_LOOPBACK = (
    "import sys\n"
    "import ray._private.services as services\n"
    "services.resolve_ip_for_localhost = lambda host: host  # keep 127.0.0.1 as given\n"
    "from ray.scripts.scripts import main\n"
    "sys.exit(main())\n"
)

RAY_START = (sys.executable, "-c", _RAY_CLI_KEEPING_LOOPBACK, "start", f"--node-ip-address={LOOPBACK}")
"""``ray start --node-ip-address=127.0.0.1``, kept on 127.0.0.1; add the node's own arguments."""
