"""Finding the loader for a folder, the same way for every benchmark."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from pathlib import Path
from typing import TypeVar

from scratchworld_dist._errors import SuiteError
from scratchworld_dist.suites._generic import BaseSuite, SuiteLoader

SuiteT = TypeVar("SuiteT", bound=BaseSuite)

Above = Callable[[Path], Sequence[Path]]
"""The folders above ``root`` that may hold the suite ``root`` is part of (a clone's ``tasks/``, say)."""


def itself(root: Path) -> Sequence[Path]:
    """No folder above: only ``root`` itself is tried."""
    return ()


def find_loader(
    root: Path, loaders: Sequence[SuiteLoader[SuiteT]], not_found: str, above: Above = itself
) -> tuple[SuiteLoader[SuiteT], Path]:
    """The first loader that recognises ``root``, else one of the folders ``above`` it (the folder it
    recognised with it); ``SuiteError(not_found, root)`` when none does."""
    for candidate in (root, *above(root)):
        for loader in loaders:
            if loader.handles(candidate):
                return loader, candidate
    raise SuiteError(not_found, root)


def load_with(
    path: str | Path, loaders: Sequence[SuiteLoader[SuiteT]], not_found: str, above: Above = itself
) -> SuiteT:
    """The suite at ``path`` (a directory), loaded by the loader that recognises it or a folder above it."""
    root = Path(path).expanduser().absolute()
    if not root.is_dir():
        raise SuiteError("not a directory" if root.exists() else "no such directory", root)
    loader, suite_root = find_loader(root, loaders, not_found, above)
    return loader.load(suite_root)
