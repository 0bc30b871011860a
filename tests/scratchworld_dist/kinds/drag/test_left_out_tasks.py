"""A drag task whose file does not load, asked for by id: the error names the file and the parse error with its
line, not just "no drag task", both from `drag validate --tasks` and from a sweep's ``tasks.ids``."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import yaml

from tests.conftest import REPO
from tests.support.cli_runner import invoke

SHIPPED = REPO / "drag-tasks"


def broken_suite(tmp: Path) -> tuple[Path, str, Path]:
    """A copy of the shipped drag suite whose first task file is not JSON (a key without its value on line 3)."""
    root = tmp / "suite"
    shutil.copytree(SHIPPED, root)
    task_id = json.loads((SHIPPED / "drag-suite.json").read_text())["tasks"][0]
    path = root / "tasks" / f"{task_id}.json"
    path.write_text(f'{{"id": "{task_id}",\n  "category": "T1",\n  "instruction"\n}}\n')
    return root, task_id, path


def test_drag_validate_names_the_file_and_line_of_a_task_that_does_not_parse(tmp_path: Path) -> None:
    root, task_id, path = broken_suite(tmp_path)
    done = invoke("drag", "validate", str(root), "--tasks", task_id)
    assert done.returncode == 2
    (line,) = done.stderr.splitlines()
    assert line.startswith(f"error: drag task {task_id!r} of suite scratchworld-drag was left out: ")
    assert f"{path}: malformed JSON: Expecting ':' delimiter: line 4 column 1" in line


def test_a_sweep_naming_a_task_that_does_not_parse_says_why_it_is_missing(tmp_path: Path) -> None:
    root, task_id, path = broken_suite(tmp_path)
    config = tmp_path / "sweep.yaml"
    sweep = {
        "name": "left-out",
        "benchmark": "drag",
        "suite": str(root),
        "agent": "oracle",
        "tasks": {"ids": [task_id]},
    }
    config.write_text(yaml.safe_dump(sweep))
    done = invoke("run", str(config), "--out", str(tmp_path / "run"))
    assert done.returncode == 2
    assert f"drag: scratchworld-drag: {path}: malformed JSON" in done.stderr  # said as it is left out
    error = done.stderr.splitlines()[-1]
    assert error.startswith(f"error: tasks.ids names drag task(s) left out of their suite: {task_id} ({path}: ")
    assert "malformed JSON: Expecting ':' delimiter: line 4 column 1" in error


def test_an_id_that_no_file_names_is_still_reported_as_not_in_the_suite(tmp_path: Path) -> None:
    root, _, _ = broken_suite(tmp_path)
    done = invoke("drag", "validate", str(root), "--tasks", "no_such_task")
    assert done.returncode == 2
    assert done.stderr.startswith("error: no drag task 'no_such_task' in suite scratchworld-drag")
