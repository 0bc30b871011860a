"""Job kinds on the worker side: what each benchmark runs, found through a registry.

The actor finds a job's kind by its spec class (``kind_of``), checks the job's harness against the
kind's fingerprint (``kind_fingerprint``: the core plus the kind's own code) and calls ``kind.run``.
Built-in kinds are ``tasks`` (episodes and regrades), ``drag``, ``perception`` and ``audit``, registered as
entry points of ``scratchworld.worker_kinds``; a plugin package registers another the same way. A kind whose jobs
run agents says where they register (``agents``: an ``AgentGroup``), which is how ``workers.agent_api`` finds them.
Importing this package and listing the kinds loads no browser stack and no LiteLLM.
"""

from workers.kinds._fingerprint import claimed_parts, kind_fingerprint
from workers.kinds._protocol import AgentGroup, WorkerHost, WorkerKind
from workers.kinds._registry import (
    DEFAULT_KIND,
    ENTRY_POINT_GROUP,
    KindRegistryError,
    agents_of,
    kind_named,
    kind_of,
    worker_kinds,
)

__all__ = [
    "DEFAULT_KIND",
    "ENTRY_POINT_GROUP",
    "AgentGroup",
    "KindRegistryError",
    "WorkerHost",
    "WorkerKind",
    "agents_of",
    "claimed_parts",
    "kind_fingerprint",
    "kind_named",
    "kind_of",
    "worker_kinds",
]
