"""docs/tour.ipynb runs: executed cell by cell in a kernel of this venv, from a temporary copy.

The notebook starts its own private Ray and real Chromium through ``api.run`` (two sweeps of two
composite oracle/noop episodes), so this is a slow browser and Ray test. It is executed by nbclient's own
command (``jupyter-execute``) in a process of its own: the kernel client's ZeroMQ sockets are closed when
that process ends, not collected in this one (where an unclosed socket's warning is an error).
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import nbformat
import pytest

from tests.conftest import REPO

pytestmark = [pytest.mark.ray, pytest.mark.browser, pytest.mark.slow, pytest.mark.timeout(900 + 300)]  # its 900 s run


KERNEL = "scratchworld-venv"


def venv_kernel(root: Path) -> None:
    """A kernel spec under ``root`` (a Jupyter path) that starts this interpreter, whatever kernels the machine has."""
    spec = root / "kernels" / KERNEL
    spec.mkdir(parents=True)
    kernel = {"argv": [sys.executable, "-m", "ipykernel_launcher", "-f", "{connection_file}"],
              "display_name": "scratchworld venv", "language": "python"}  # fmt: skip
    (spec / "kernel.json").write_text(json.dumps(kernel))


def outputs_text(cell: nbformat.NotebookNode) -> str:
    parts: list[str] = []
    for output in cell.get("outputs", []):
        parts.append(output.get("text", ""))
        parts.append(output.get("data", {}).get("text/plain", ""))
    return "\n".join(parts)


def test_tour_notebook_executes(tmp_path: Path) -> None:
    copy = tmp_path / "tour.ipynb"
    shutil.copyfile(REPO / "docs" / "tour.ipynb", copy)
    venv_kernel(tmp_path / "jupyter")
    command = [str(Path(sys.executable).with_name("jupyter-execute")), "--inplace", f"--kernel_name={KERNEL}"]
    env = {**os.environ, "JUPYTER_PATH": str(tmp_path / "jupyter")}
    done = subprocess.run([*command, str(copy)], cwd=tmp_path, env=env, capture_output=True, text=True, timeout=900)
    assert done.returncode == 0, done.stderr[-4000:]  # a failing cell: its traceback
    notebook = nbformat.read(copy, as_version=4)

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
