"""Writes each task's initial.sb3 and golden.sb3 from its project.py.

    python tasks/build_projects.py          # rebuild what changed
    python tasks/build_projects.py --check  # exit 1 if a committed .sb3 is out of date

A task's project.py defines ``initial()`` and, optionally, ``golden()``, each returning a
``scratchworld_dist.sb3.Project``. The builder is deterministic, so unchanged sources give
byte-identical files.
"""

from __future__ import annotations

import argparse
import importlib.util
import sys
from pathlib import Path

SUITE = Path(__file__).resolve().parent


def built_projects(task_dir: Path) -> dict[str, bytes]:
    """File name -> bytes, for every project the task's project.py defines."""
    spec = importlib.util.spec_from_file_location(f"task_project_{task_dir.name}", task_dir / "project.py")
    if spec is None or spec.loader is None:
        raise ImportError(f"cannot import {task_dir / 'project.py'}")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    files = {"initial.sb3": module.initial().to_sb3()}
    if hasattr(module, "golden"):
        files["golden.sb3"] = module.golden().to_sb3()
    return files


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--check", action="store_true", help="only report out-of-date files")
    check = parser.parse_args().check
    stale = []
    for source in sorted(SUITE.glob("*/*/project.py")):
        for name, data in built_projects(source.parent).items():
            path = source.parent / name
            if path.is_file() and path.read_bytes() == data:
                continue
            stale.append(path)
            if not check:
                path.write_bytes(data)
    for path in stale:
        print(f"{'out of date' if check else 'wrote'}: {path.relative_to(SUITE)}")
    return 1 if check and stale else 0


if __name__ == "__main__":
    sys.exit(main())
