"""One-task suites built in a test's tmp folder from our suite's files: in our layout, and as an upstream clone."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

from tests.conftest import DATA, SUITE_DIR

TASK = "sum_two_numbers"
TASK_DIR = SUITE_DIR / "compute" / TASK
GOLDEN = TASK_DIR / "golden.sb3"


def native_suite(root: Path, task_name: str = TASK) -> Path:
    """A one-task suite in our layout (a copy of sum_two_numbers, named ``task_name``); returns the task folder."""
    (root / "compute").mkdir(parents=True)
    for name in ("suite.json", "harness.js"):
        shutil.copy(SUITE_DIR / name, root / name)
    task = root / "compute" / task_name
    task.mkdir()
    for name in ("task.json", "evaluate.js", "initial.sb3", "golden.sb3", "golden_trajectory.json"):
        if (TASK_DIR / name).exists():
            shutil.copy(TASK_DIR / name, task / name)
    return task


def upstream_clone(root: Path, name: str = "calc") -> Path:
    """A minimal clone of the upstream layout: one compute task, its project, its script and the helper."""
    (root / "tasks" / "compute").mkdir(parents=True)
    (root / "scratch-gui" / "static").mkdir(parents=True)
    scripts = root / "scratch-bench-api" / "api" / "evaluation_scripts"
    scripts.mkdir(parents=True)
    shutil.copy(DATA / "upstream_scripts" / "evaluation_utils.js", scripts)
    shutil.copy(DATA / "loads_only.js", scripts / f"{name}.js")
    shutil.copy(TASK_DIR / "initial.sb3", root / "scratch-gui" / "static" / f"{name}.sb3")
    task = {"type": "compute", "instruction": "Add two numbers.", "initial_project": f"{name}.sb3"}
    (root / "tasks" / "compute" / f"{name}.json").write_text(json.dumps(task))
    return root
