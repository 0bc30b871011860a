"""Public surfaces: every package's __all__ is complete and sorted, and its lazy exports resolve."""

from __future__ import annotations

import importlib

import pytest

PACKAGES = [
    "scratchworld_dist",
    "scratchworld_dist.kinds.drag.items",
    "scratchworld_dist.sb3.editing",
    "scratchworld_dist.memory",
    "scratchworld_dist.kinds.perception.items",
    "scratchworld_dist.kinds.tasks.report",
    "scratchworld_dist.reports",
    "scratchworld_dist.results",
    "scratchworld_dist.scheduling",
    "scratchworld_dist.suites",
    "scratchworld_dist.sb3",
    "scratchworld_dist.sweep",
    "scratchworld_dist.viewer",
    "workers",
    "workers.agent_api",
    "workers.agents",
    "workers.composite",
    "workers.contract",
    "workers.kinds.drag",
    "workers.editor",
    "workers.kinds.tasks",
    "workers.evaluation",
    "workers.llm",
    "workers.node",
    "workers.ocr",
    "workers.kinds.perception",
    "workers.primitive",
]


@pytest.mark.parametrize("name", PACKAGES)
def test_all_is_complete_and_sorted(name: str) -> None:
    module = importlib.import_module(name)
    for member in module.__all__:
        getattr(module, member)  # a lazy export (workers.lazy_exports) is imported here, so it is in vars below
    public = [
        member
        for member, value in vars(module).items()
        if not member.startswith("_") and not (hasattr(value, "__path__") or type(value).__name__ == "module")
    ]
    assert sorted(module.__all__) == sorted(public)
    # Constants, then classes, then functions, each alphabetical (ruff's RUF022 order).
    assert list(module.__all__) == sorted(module.__all__, key=lambda s: (not s.isupper(), not s[0].isupper(), s))


def test_one_exception_hierarchy() -> None:
    import scratchworld_dist
    from scratchworld_dist import ScratchWorldError

    errors = [getattr(scratchworld_dist, n) for n in scratchworld_dist.__all__ if n.endswith("Error")]
    assert all(issubclass(e, ScratchWorldError) for e in errors)
