"""Plugin packages made for a test: modules and entry points written into a project, installed with pip into a
folder of their own (put on the path by the test), so the venv is left as it was and the registries find them
through real distribution metadata."""

from __future__ import annotations

import subprocess
import sys
from collections.abc import Mapping
from pathlib import Path


def install_plugin(
    root: Path, name: str, modules: Mapping[str, str], entry_points: Mapping[str, Mapping[str, str]]
) -> Path:
    """Distribution ``name`` (version 1.0) holding ``modules`` (top-level module name: source) and registering
    ``entry_points`` (group: {entry point name: ``module:attribute``}), installed into ``root/site``: returned."""
    package = root / "pkg"
    package.mkdir(parents=True)
    lines = [
        "[build-system]",
        'requires = ["setuptools"]',
        'build-backend = "setuptools.build_meta"',
        "",
        "[project]",
        f'name = "{name}"',
        'version = "1.0"',
        "",
        "[tool.setuptools]",
        f"py-modules = [{', '.join(repr(module) for module in modules)}]",
    ]
    for group, points in entry_points.items():
        lines += ["", f'[project.entry-points."{group}"]', *(f'{point} = "{value}"' for point, value in points.items())]
    (package / "pyproject.toml").write_text("\n".join(lines) + "\n")
    for module, source in modules.items():
        (package / f"{module}.py").write_text(source)
    site = root / "site"
    command = [sys.executable, "-m", "pip", "install", "--quiet", "--no-deps", "--no-build-isolation"]
    subprocess.run([*command, "--target", str(site), str(package)], check=True, capture_output=True, timeout=300)
    return site


def install_package(root: Path, files: Mapping[str, str]) -> Path:
    """A package given whole (``pyproject.toml`` and its modules, by path), installed into ``root/site``: returned."""
    package = root / "pkg"
    for path, text in files.items():
        (package / path).parent.mkdir(parents=True, exist_ok=True)
        (package / path).write_text(text)
    site = root / "site"
    command = [sys.executable, "-m", "pip", "install", "--quiet", "--no-deps", "--no-build-isolation"]
    subprocess.run([*command, "--target", str(site), str(package)], check=True, capture_output=True, timeout=300)
    return site
