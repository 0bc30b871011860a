"""docs/tour.ipynb runs: executed cell by cell in a kernel of this venv, from a temporary copy.

The notebook starts its own private Ray and real Chromium through ``api.run`` (two sweeps of two
composite oracle/noop episodes), so this is a slow browser and Ray test.
"""

from __future__ import annotations

import json
import shutil
import sys
from pathlib import Path

import nbformat
import pytest
from jupyter_client.kernelspec import KernelSpecManager
from jupyter_client.manager import KernelManager
from nbclient import NotebookClient

from tests.conftest import REPO

pytestmark = [pytest.mark.ray, pytest.mark.browser, pytest.mark.slow]


def venv_kernel(root: Path) -> KernelManager:
    """A kernel spec that starts this interpreter (the venv's), whatever kernels the machine has."""
    spec = root / "kernels" / "scratchworld-venv"
    spec.mkdir(parents=True)
    kernel = {"argv": [sys.executable, "-m", "ipykernel_launcher", "-f", "{connection_file}"],
              "display_name": "scratchworld venv", "language": "python"}  # fmt: skip
    (spec / "kernel.json").write_text(json.dumps(kernel))
    specs = KernelSpecManager(kernel_dirs=[str(root / "kernels")])
    return KernelManager(kernel_name="scratchworld-venv", kernel_spec_manager=specs)


def outputs_text(cell: nbformat.NotebookNode) -> str:
    parts: list[str] = []
    for output in cell.get("outputs", []):
        parts.append(output.get("text", ""))
        parts.append(output.get("data", {}).get("text/plain", ""))
    return "\n".join(parts)


def test_tour_notebook_executes(tmp_path: Path) -> None:
    copy = tmp_path / "tour.ipynb"
    shutil.copyfile(REPO / "docs" / "tour.ipynb", copy)
    notebook = nbformat.read(copy, as_version=4)
    client = NotebookClient(
        notebook,
        timeout=900,
        km=venv_kernel(tmp_path),
        resources={"metadata": {"path": str(tmp_path)}},
    )
    client.execute()  # raises CellExecutionError, with the cell and its traceback, if any cell fails

    code = [cell for cell in notebook.cells if cell.cell_type == "code"]
    assert not [o for cell in code for o in cell.outputs if o.output_type == "error"]
    text = "\n".join(outputs_text(cell) for cell in code)
    assert "demo: 2 job(s) to run" in text, text
    assert "oracle: planned 2, outcomes {'passed': 2, 'failed': 0, 'error': 0}" in text, text
    assert "noop: planned 2, outcomes {'passed': 0, 'failed': 2, 'error': 0}" in text, text
    assert "paired jobs: 2 over 2 tasks" in text, text
    assert "SR oracle 100%, noop 0%, difference +100%" in text, text
    assert any("image/png" in o.get("data", {}) for cell in code for o in cell.outputs), "no plot drawn"
    saved = [line.split("saved ", 1)[1] for line in text.splitlines() if line.startswith("saved ")]
    assert saved and Path(saved[0]).stat().st_size > 1000  # the PNG the plot cell wrote
