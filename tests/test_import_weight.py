"""What importing a part of the package loads: the driver, reports and plugins never pull in the browser stack
(nor matplotlib, which only an HTML report's plots need).

Each import runs in a fresh interpreter, since this test process has long loaded everything.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from tests.support.run_dirs import job, make_run

BROWSER_STACK = ("playwright", "cv2", "numpy", "rapidocr", "onnxruntime", "litellm", "ray", "pyarrow", "matplotlib")


def loaded_after(statement: str) -> set[str]:
    probe = f"import json, sys\n{statement}\nprint(json.dumps(sorted(sys.modules)))"
    done = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    return {name.split(".")[0] for name in json.loads(done.stdout.splitlines()[-1])}


@pytest.mark.parametrize(
    ("statement", "allowed"),
    [
        ("import scratchworld_dist", ()),
        ("import workers.contract", ()),
        ("import workers.node; workers.node.harness_fingerprint()", ()),
        # The job kinds and their fingerprints: the driver plans with them; the runners are imported per job.
        (
            "from workers.kinds import kind_fingerprint; from workers.node import harness_fingerprint\n"
            "kind_fingerprint(harness_fingerprint(), 'drag')",
            (),
        ),
        # A kind's package (what its entry point names, and where its contract models are): its runner is not loaded.
        ("import workers.kinds.tasks, workers.kinds.drag, workers.kinds.perception, workers.kinds.audit", ()),
        # The agent registry, which finds a kind's agents through the worker kinds' registry (loading no agent).
        ("from workers.agent_api import registered_agents; registered_agents('drag'), registered_agents()", ()),
        # Reports and status read Parquet (pyarrow, which brings numpy), but start no browser.
        ("from scratchworld_dist.cli import main", ("pyarrow", "numpy")),
        ("import scratchworld_dist.reports, scratchworld_dist.results", ("pyarrow", "numpy")),
    ],
)
def test_an_import_loads_only_what_it_needs(statement: str, allowed: tuple[str, ...]) -> None:
    heavy = loaded_after(statement) & set(BROWSER_STACK)
    assert heavy <= set(allowed), f"{statement} loads {sorted(heavy - set(allowed))}"


def test_the_cli_loads_the_browser_stack_only_for_commands_that_need_it(tmp_path: Path) -> None:
    missing = json.dumps(str(tmp_path / "no-run"))
    loaded = loaded_after(
        "from click.testing import CliRunner\n"
        "from scratchworld_dist.cli._main import cli\n"
        f"assert CliRunner().invoke(cli, ['status', {missing}]).exit_code != 0\n"
        f"assert CliRunner().invoke(cli, ['report', {missing}]).exit_code != 0"
    )
    assert not loaded & {"playwright", "cv2", "ray", "litellm"}, sorted(loaded & set(BROWSER_STACK))


def test_only_an_html_report_draws_with_matplotlib(tmp_path: Path) -> None:
    run = json.dumps(str(make_run(tmp_path / "run", [job("a"), job("b", "failed")], planned=2, tasks=2)))
    invoke = "from click.testing import CliRunner\nfrom scratchworld_dist.cli._main import cli\n"
    for fmt in ("md", "json"):
        loaded = loaded_after(
            f"{invoke}assert CliRunner().invoke(cli, ['report', {run}, '--format', '{fmt}']).exit_code == 0"
        )
        assert "matplotlib" not in loaded, fmt
    status = loaded_after(f"{invoke}assert CliRunner().invoke(cli, ['status', {run}]).exit_code == 0")
    assert "matplotlib" not in status
    html = loaded_after(f"{invoke}assert CliRunner().invoke(cli, ['report', {run}, '--format', 'html']).exit_code == 0")
    assert "matplotlib" in html


def test_trackers_and_the_tracing_sdk_load_only_when_asked_for() -> None:
    """A run without ``loggers:`` nor ``OTEL_*`` variables imports neither tracker nor the OpenTelemetry SDK."""
    probe = (
        "import json, sys\n"
        "import scratchworld_dist._run, scratchworld_dist.trackers, workers.actor, workers.kinds.tasks._runner\n"
        "from workers.tracing import tracing_active\n"
        "assert not tracing_active()\n"
        "print(json.dumps(sorted(sys.modules)))"
    )
    environ = {k: v for k, v in os.environ.items() if not k.startswith(("OTEL_", "MLFLOW_", "WANDB_"))}
    done = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, timeout=120, env=environ)
    assert done.returncode == 0, done.stderr
    loaded = json.loads(done.stdout.splitlines()[-1])
    assert not [name for name in loaded if name.split(".")[0] in ("mlflow", "wandb")]
    assert not [name for name in loaded if name.startswith(("opentelemetry.sdk", "opentelemetry.exporter"))]
