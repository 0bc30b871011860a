"""Collecting every problem of a suite before failing, so one run shows them all."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any, TypeVar

from pydantic import BaseModel, ValidationError

from scratchworld_dist._errors import SuiteError
from scratchworld_dist._files import read_text

ModelT = TypeVar("ModelT", bound=BaseModel)


class SuiteProblems:
    """(file, message) pairs that become one ``SuiteError`` naming each file."""

    def __init__(self, root: Path) -> None:
        self.root = root
        self.items: list[tuple[Path, str]] = []

    def add(self, path: Path, message: str) -> None:
        self.items.append((path, message))

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
        if not self.items:
            return
        if len(self.items) == 1:
            path, message = self.items[0]
            raise SuiteError(message, path)
        lines = "\n".join(f"  {path}: {message}" for path, message in self.items)
        raise SuiteError(f"{len(self.items)} problems in the suite at {self.root}:\n{lines}")
