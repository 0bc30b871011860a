"""Run directories written before the results named their benchmark (schema 3, ``tests/data/runs_v3``) still
read, report as they did and resume."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest

from scratchworld_dist.results import SCHEMA_VERSION, RunStore, kind_of_run
from tests.conftest import DATA
from tests.support.cli_runner import invoke
from tests.support.sweep_driver import run_here

OLD_RUNS = DATA / "runs_v3"
KINDS = {"episodes": "tasks", "drag": "drag", "perception": "perception"}
"""Each kept run's folder and the kind it holds."""


def old_run(tmp_path: Path, folder: str) -> Path:
    """A copy of a kept run (they are never written to), at a path of its own."""
    copy = tmp_path / folder
    shutil.copytree(OLD_RUNS / folder, copy)
    return copy


def as_kept(report: str, run_dir: Path) -> str:
    """A report with the run's own path in place of wherever the run directory was."""
    recorded = json.loads((run_dir / "manifest.json").read_text())["config"]["output"]
    return report.replace(str(run_dir), "RUN").replace(recorded, "RUN")


@pytest.mark.parametrize("folder", list(KINDS))
def test_an_old_run_reads_and_reports_as_it_did(tmp_path: Path, folder: str) -> None:
    run_dir = old_run(tmp_path, folder)
    assert json.loads((run_dir / "manifest.json").read_text())["schema_version"] == 3 < SCHEMA_VERSION
    assert kind_of_run(run_dir).name == KINDS[folder]
    rows = RunStore(run_dir).job_rows()
    assert rows and {row.benchmark for row in rows} == {KINDS[folder]}  # no column in its shards: the run's kind
    status = invoke("status", str(run_dir))
    assert status.returncode == 0 and "not yet run 0;" in " ".join(status.stdout.split()), status.stdout
    report = invoke("report", str(run_dir))
    assert report.returncode == 0, report.stderr
    kept = (run_dir / "report.md").read_text()  # what the run printed and kept when it was made
    assert as_kept(report.stdout, run_dir).strip() == as_kept(kept, run_dir).strip()


def test_old_runs_of_three_kinds_make_one_diagnosis(tmp_path: Path) -> None:
    runs = [old_run(tmp_path, folder) for folder in KINDS]
    done = invoke("report", *map(str, runs), "--format", "json")
    assert done.returncode == 0, done.stderr
    diagnosis = json.loads(done.stdout)["diagnosis"]
    assert set(diagnosis["runs"]) == set(KINDS.values())
    oracle = next(row for row in diagnosis["rows"] if row["agent"] == "oracle")
    assert oracle["composite_sr"]["value"] == oracle["primitive_sr"]["value"] == 1.0
    assert oracle["drag_pass_at_1"]["baseline"]["value"] == 1.0
    assert oracle["perception"]["ALL"]["normalized"] == 1.0


@pytest.mark.ray
def test_an_old_run_resumes_under_this_code(tmp_path: Path, shared_ray: int) -> None:
    """Another harness planned the old rows, so resuming needs --force, for that reason alone (not for the
    schema): the old rows are kept as stale, the jobs run again under this code, the report shows those."""
    run_dir = old_run(tmp_path, "perception")
    config = OLD_RUNS / "configs" / "perception.yaml"
    code, out = run_here(config, "--out", str(run_dir))
    assert code != 0 and "harness fingerprint 433e91e37d952023 ->" in out and "result schema" not in out, out
    code, out = run_here(config, "--out", str(run_dir), "--force")
    assert code == 0, out
    rows = RunStore(run_dir).job_rows()
    assert len(rows) == 12 and {row.benchmark for row in rows} == {"perception"}
    current = [row for row in rows if row.harness_fingerprint != "433e91e37d952023"]
    assert len(current) == 6 and sorted(row.outcome for row in current) == ["failed"] * 2 + ["passed"] * 4
    report = invoke("report", str(run_dir))
    assert report.returncode == 0 and report.stdout.startswith("# ScratchWorld perception report"), report.stderr
    assert "| oracle | 3 | 3 |" in report.stdout or "100.0%" in report.stdout
    assert invoke("status", str(run_dir)).returncode == 0
