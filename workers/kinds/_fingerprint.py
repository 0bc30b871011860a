"""The harness fingerprint of a kind's jobs: the core plus that kind's own code.

A job's id, its rows and its run's manifest carry the digest of what can change its outcome. The
full fingerprint (``workers.node.harness_fingerprint``, what nodes report and compare) covers all of
``workers/``; a kind's jobs are planned and checked under it minus the code only OTHER kinds import,
so editing drag code leaves episode and perception runs resumable, and the drag runs refuse.

Each built-in kind claims its whole folder, ``workers/kinds/<name>/`` (``WorkerKind.code``): neither the core
nor another kind imports anything there (a path may be claimed only then; what is shared stays core). The
browser, editor pool and evaluator every kind runs in are the worker's (``workers/actor``, ``editor``,
``evaluation``), and what several kinds use (``agents``' coordinate helpers and model calls, ``primitive``'s
element list, ``composite``, ``ocr``, ``llm``) is core: an edit there changes every kind's digest, which is the
safe side. A plugin kind's code lies outside ``workers/`` and claims nothing: it names its own version in its
jobs' ids.

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
