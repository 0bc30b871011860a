"""``scratchworld regrade`` of a run in a bucket (moto's S3 server on 127.0.0.1): a real oracle episode in
Chromium written to ``s3://...``, its final project read back from the bucket and evaluated again."""

from __future__ import annotations

from pathlib import Path

import pytest
import yaml

from scratchworld_dist.results import RunStore, read_manifest
from scratchworld_dist.results.remote._location import parse_location
from tests.conftest import REPO
from tests.support.cli_runner import invoke
from tests.support.s3_server import S3Server
from tests.support.sweep_driver import run_here


@pytest.mark.browser
@pytest.mark.slow
def test_regrade_evaluates_the_final_projects_of_a_remote_run_again(
    tmp_path: Path, s3: S3Server, shared_ray: int
) -> None:
    url = f"s3://{s3.bucket()}/sweeps/source"
    config = {
        "name": "source",
        "suite": str(REPO / "tasks"),
        "agent": "oracle",
        "tasks": {"ids": ["sum_two_numbers"]},
        "episodes": {"modes": ["composite"]},
        "limits": {"episode_timeout_s": 240, "pages_per_worker": 1},
        "output": url,
        "storage": {"cache_dir": str(tmp_path / "mirrors")},
    }
    (tmp_path / "sweep.yaml").write_text(yaml.safe_dump(config))
    code, out = run_here(tmp_path / "sweep.yaml", "--progress", "none")
    assert code == 0, out

    done = invoke("regrade", url, "--out", str(tmp_path / "regrade"), "--clock", "real")
    assert done.returncode == 0, done.stdout + done.stderr
    assert "verdicts: 1 unchanged, 0 changed" in " ".join((done.stdout + done.stderr).split())
    manifest = read_manifest(tmp_path / "regrade")
    assert manifest is not None and manifest.regrade is not None
    assert manifest.regrade.source_run == url  # the source by its URL, not the local view it was read through
    (row,) = RunStore(tmp_path / "regrade").job_rows()
    bucket, prefix = parse_location(url).root.split("/", 1)
    (final,) = [key for key in s3.keys(bucket, prefix) if key.endswith("final.sb3")]
    assert (tmp_path / "regrade" / str(row.artifact_dir) / "final.sb3").read_bytes() == s3.read(bucket, final)
