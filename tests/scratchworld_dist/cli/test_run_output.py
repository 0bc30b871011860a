"""What ``scratchworld run`` prints in a process of its own, piped: where the workers log, and none of Ray's
notices about a cluster the user did not ask for (a private local Ray serves this machine only)."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from tests.conftest import REPO
from tests.support.sweep_driver import Driver, run


@pytest.mark.ray
@pytest.mark.browser
@pytest.mark.slow
def test_a_private_run_names_its_worker_logs_and_prints_no_ray_notice(tmp_path: Path, drivers: list[Driver]) -> None:
    config = tmp_path / "demo.yaml"
    config.write_text((REPO / "configs" / "demo.yaml").read_text().replace("../tasks", str(REPO / "tasks")))
    code, log = run(drivers, config, "--limit", "1", "--modes", "composite", "--out", str(tmp_path / "run"))
    assert code == 0, log
    assert "Token authentication" not in log and "RAY_AUTH_MODE" not in log
    (logs,) = re.findall(r"^worker logs: (\S+)$", log, re.MULTILINE)
    assert Path(logs).is_dir() and any(Path(logs).glob("worker-*"))  # where the workers' own output went
