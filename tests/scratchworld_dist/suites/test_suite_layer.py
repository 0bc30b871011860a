"""The generic suite layer: a fourth benchmark's suites load through the same detector and problem model."""

from __future__ import annotations

from pathlib import Path

import pytest
from pydantic import BaseModel

from scratchworld_dist import SuiteError
from scratchworld_dist.suites import BaseSuite, SuiteKind, SuiteProblem, find_loader, load_with


class Note(BaseModel):
    id: str


class NoteSuite(BaseSuite[Note]):
    pass


class NoteLoader:
    kind: SuiteKind = "scratchworld_dist"

    @staticmethod
    def handles(root: Path) -> bool:
        return (root / "notes.txt").is_file()

    def load(self, root: Path) -> NoteSuite:
        lines = (root / "notes.txt").read_text().splitlines()
        problems = [
            SuiteProblem(path=root / "notes.txt", message=f"line {n}: empty") for n, s in enumerate(lines) if not s
        ]
        return NoteSuite(
            name="notes", kind=self.kind, root=root, items=tuple(Note(id=s) for s in lines if s), problems=problems
        )


def _above(root: Path) -> tuple[Path, ...]:
    return (root.parent,) if root.name == "inner" else ()


def test_load_with_finds_the_loader_here_or_above(tmp_path: Path) -> None:
    (tmp_path / "notes.txt").write_text("a\n\nb\n")
    (tmp_path / "inner").mkdir()
    suite = load_with(tmp_path / "inner", [NoteLoader()], "not notes", _above)
    assert isinstance(suite, NoteSuite) and suite.root == tmp_path
    assert [n.id for n in suite.items] == ["a", "b"]
    assert [str(p) for p in suite.problems] == [f"{tmp_path / 'notes.txt'}: line 1: empty"]
    with pytest.raises(SuiteError, match="line 1: empty"):
        suite.raise_for_problems()


def test_load_with_names_what_it_expected(tmp_path: Path) -> None:
    with pytest.raises(SuiteError, match="not notes"):
        find_loader(tmp_path, [NoteLoader()], "not notes")
    with pytest.raises(SuiteError, match="no such directory"):
        load_with(tmp_path / "missing", [NoteLoader()], "not notes")
