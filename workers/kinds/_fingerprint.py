"""The harness fingerprint of a kind's jobs: the core plus that kind's own code.

A job's id, its rows and its run's manifest carry the digest of what can change its outcome. The
full fingerprint (``workers.node.harness_fingerprint``, what nodes report and compare) covers all of
``workers/``; a kind's jobs are planned and checked under it minus the code only OTHER kinds import,
so editing drag code leaves episode and perception runs resumable, and the drag runs refuse.

What each built-in kind claims (``WorkerKind.code``), decided from the imports (a path may be claimed
only when neither the core nor another kind's runner imports it; what is shared stays core):

- ``drag``: ``workers/kinds/drag/`` and its dispatch ``workers/kinds/drag/_run.py``. Drag's runner imports
  ``agents`` (coordinate helpers, prompts, model calls), ``primitive`` (element list, settle), ``editor``
  and ``llm``: those stay core.
- ``perception``: ``workers/kinds/perception/`` and ``workers/kinds/perception/_run.py``. It imports ``agents``
  (model calls) and ``llm``: core.
- ``audit``: ``workers/kinds/audit/_run.py``; the evaluation it runs is the episodes' (core).
- ``tasks``: only ``workers/kinds/tasks/_run.py``. The episode code cannot be claimed today:
  ``workers/kinds/tasks`` holds the actor itself, whose ``EpisodeRunner`` owns the browser and editor pool
  every browser kind runs in (so ``evaluation``, ``composite``, ``ocr`` and ``agent_api``, which it
  imports, are imported by every worker), and ``agents`` and ``primitive`` serve drag too. An edit
  there changes every kind's digest, which is the safe side.

Everything under ``workers/`` that no kind claims is core: contract, node, editor, llm, agents,
the actor, this package, and the page JavaScript, packages, editor bundle and browser parts.
``tests/workers/test_worker_kinds.py`` checks the claims against the imports.
"""

from __future__ import annotations

from workers.contract import HarnessFingerprint
from workers.kinds._protocol import WorkerKind
from workers.kinds._registry import kind_named, worker_kinds


def claimed_parts(kind: WorkerKind) -> tuple[str, ...]:
    """The fingerprint part names (or folder prefixes, ending in ``/``) of a kind's own code."""
    return tuple(f"workers/{path}" if path.endswith(".py") else f"workers/{path.rstrip('/')}/" for path in kind.code)


def kind_fingerprint(
    full: HarnessFingerprint, kind: str, kinds: dict[str, WorkerKind] | None = None
) -> HarnessFingerprint:
    """``full`` without the code the other kinds claim: what ``kind``'s jobs are planned and checked under."""
    kinds = worker_kinds() if kinds is None else kinds
    kind_named(kind, kinds)  # an unknown kind is an error, not the full fingerprint
    others = tuple(part for name, other in kinds.items() if name != kind for part in claimed_parts(other))
    return full.without(others)
