"""One problem model for every suite, and the reader that collects problems so one run shows them all."""

from __future__ import annotations

import json
from collections.abc import Iterable
from pathlib import Path
from typing import Any, Literal, TypeVar

from pydantic import BaseModel, ConfigDict, ValidationError

from scratchworld_dist._errors import SuiteError
from scratchworld_dist._files import read_text

ModelT = TypeVar("ModelT", bound=BaseModel)

ProblemEffect = Literal["skipped", "no_view", "corrected"]
"""``skipped``: the item is not in the suite; ``no_view``: it is, with ``view`` None (drag);
``corrected``: it is, with an upstream label replaced by what its project says (drag)."""


class SuiteProblem(BaseModel):
    """Something in a suite that could not be used as it is, naming its file (and line, in a JSON-lines file)."""

    model_config = ConfigDict(frozen=True)

    path: Path
    message: str
    """One line, naming the field at fault."""

    item_id: str | None = None
    """The item it belongs to, when one could be named."""

    effect: ProblemEffect = "skipped"

    def __str__(self) -> str:
        return f"{self.path}: {self.message}"


def raise_problems(root: Path, problems: Iterable[SuiteProblem]) -> None:
    """One ``SuiteError`` naming every problem (the file itself when there is one), or nothing."""
    found = list(problems)
    if not found:
        return
    if len(found) == 1:
        raise SuiteError(found[0].message, found[0].path)
    lines = "\n".join(f"  {problem}" for problem in found)
    raise SuiteError(f"{len(found)} problems in the suite at {root}:\n{lines}")


class SuiteProblems:
    """Problems recorded while reading a suite's files, kept to report together rather than one at a time."""

    def __init__(self, root: Path) -> None:
        self.root = root
        self.items: list[SuiteProblem] = []

    def add(self, path: Path, message: str) -> None:
        self.items.append(SuiteProblem(path=path, message=message))

    def of_item(self, item_id: str | None, effect: ProblemEffect = "skipped") -> list[SuiteProblem]:
        """What was recorded, as problems of the item ``item_id``."""
        return [problem.model_copy(update={"item_id": item_id, "effect": effect}) for problem in self.items]

    def read_json(self, path: Path) -> Any | None:
        """The parsed file, or None with the reason recorded."""
        try:
            return json.loads(read_text(path))
        except FileNotFoundError:
            self.add(path, "missing")
        except (OSError, UnicodeDecodeError) as exc:
            self.add(path, f"cannot read: {exc}")
        except json.JSONDecodeError as exc:
            self.add(path, f"malformed JSON: {exc}")
        return None

    def read_model(self, path: Path, model: type[ModelT]) -> ModelT | None:
        """The file validated as ``model``, or None with every field error recorded."""
        data = self.read_json(path)
        if data is None:
            return None
        try:
            return model.model_validate(data)
        except ValidationError as exc:
            fields = "; ".join(f"{'.'.join(map(str, e['loc'])) or 'file'}: {e['msg']}" for e in exc.errors())
            self.add(path, fields)
            return None

    def raise_if_any(self) -> None:
        raise_problems(self.root, self.items)
