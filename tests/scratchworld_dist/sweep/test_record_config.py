"""``record: {video: true, fps: N}``: what a sweep records besides the steps changes no job and no run identity."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from scratchworld_dist._errors import ConfigError
from scratchworld_dist._sweep_manifest import config_hash
from scratchworld_dist.sweep import plan_run, sweep_config_from, worker_job
from tests.conftest import REPO
from workers.contract import RecordSettings

BASE = {
    "name": "video",
    "suite": str(REPO / "tasks"),
    "agent": "oracle",
    "tasks": {"ids": ["quiz_score", "sum_two_numbers"]},
    "episodes": {"modes": ["composite", "primitive"]},
}


def test_recording_a_video_changes_no_job_id_and_no_config_hash(tmp_path: Path) -> None:
    plain = sweep_config_from(dict(BASE), tmp_path)
    filmed = sweep_config_from({**BASE, "record": {"video": True, "fps": 8}}, tmp_path)
    assert filmed.record == RecordSettings(video=True, fps=8)
    assert plain.record == RecordSettings()  # off unless asked for
    assert config_hash(filmed) == config_hash(plain)  # a run may turn it on or off when it resumes
    plain_jobs, filmed_jobs = plan_run(plain).jobs, plan_run(filmed).jobs
    assert [job.job_id for job in filmed_jobs] == [job.job_id for job in plain_jobs]
    assert len(filmed_jobs) == 4
    specs = [worker_job(job, 1, 60) for job in filmed_jobs]
    assert {spec.record for spec in specs} == {RecordSettings(video=True, fps=8)}  # type: ignore[attr-defined]
    assert {worker_job(job, 1, 60).record for job in plain_jobs} == {RecordSettings()}  # type: ignore[attr-defined]


@pytest.mark.parametrize(
    ("record", "problem"),
    [
        ({"video": True, "fps": 0}, "record.fps: Input should be greater than or equal to 1"),
        ({"video": True, "fps": 31}, "record.fps: Input should be less than or equal to 30"),
        ({"vidoe": True}, "record.vidoe"),
    ],
)
def test_bad_record_settings_are_named(tmp_path: Path, record: dict[str, object], problem: str) -> None:
    with pytest.raises(ConfigError, match=re.escape(problem)):
        sweep_config_from({**BASE, "record": record}, tmp_path)


def test_a_benchmark_without_episodes_refuses_a_video(tmp_path: Path) -> None:
    config = {"name": "d", "benchmark": "drag", "suite": str(REPO / "drag-tasks"), "agent": "oracle"}
    refused = "record.video records agent episodes; the drag benchmark has none"
    with pytest.raises(ConfigError, match=re.escape(refused)):
        sweep_config_from({**config, "record": {"video": True}}, tmp_path)
