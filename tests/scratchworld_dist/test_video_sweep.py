"""A sweep with ``record: {video: true}`` runs the same jobs as one without and reaches the same verdicts; its
attempts carry ``video.mp4`` (and ``video.json``), which the job page plays and ``view --export`` carries."""

from __future__ import annotations

import io
import json
from pathlib import Path

import av
import pytest
import yaml

from scratchworld_dist.results import RunStore, effective_rows
from scratchworld_dist.viewer import ViewerSite, export_site
from tests.conftest import REPO
from tests.support.sweep_driver import run_here
from workers.contract import VideoInfo

pytestmark = [pytest.mark.ray, pytest.mark.browser, pytest.mark.slow, pytest.mark.timeout(900)]

TASKS = ["quiz_score"]
"""One task in both modes: its primitive gestures click and drag, which the video's markers show."""


def write_config(tmp_path: Path, name: str, **fields: object) -> Path:
    config = {
        "name": name,
        "suite": str(REPO / "tasks"),
        "agent": "oracle",
        "tasks": {"ids": TASKS},
        "episodes": {"modes": ["composite", "primitive"], "max_steps": {"composite": 100, "primitive": 300}},
        "limits": {"pages_per_worker": 1, "retries": 1},
        "output": str(tmp_path / name),
        **fields,
    }
    path = tmp_path / f"{name}.yaml"
    path.write_text(yaml.safe_dump(config))
    return path


def verdicts(run_dir: Path) -> dict[str, tuple[str, int, int, str, int | None]]:
    return {
        row.job_id: (row.outcome, row.tests_passed, row.tests_total, row.stop_reason, row.steps)
        for row in effective_rows(RunStore(run_dir).job_rows())
    }


def test_the_same_jobs_reach_the_same_verdicts_with_a_video_which_the_viewer_plays(
    tmp_path: Path, shared_ray: int
) -> None:
    plain_config = write_config(tmp_path, "plain")
    filmed_config = write_config(tmp_path, "filmed", record={"video": True, "fps": 5})
    code, out = run_here(plain_config, "--progress", "none")
    assert code == 0, out
    code, out = run_here(filmed_config, "--progress", "none")
    assert code == 0, out

    plain, filmed = verdicts(tmp_path / "plain"), verdicts(tmp_path / "filmed")
    assert filmed == plain  # the same job ids, each with the same outcome, tests, stop and step count
    assert len(plain) == 2 and {v[0] for v in plain.values()} == {"passed"}
    assert not list((tmp_path / "plain" / "artifacts").rglob("video.*"))

    rows = list(effective_rows(RunStore(tmp_path / "filmed").job_rows()))
    for row in rows:
        folder = tmp_path / "filmed" / str(row.artifact_dir)
        info = VideoInfo.model_validate_json((folder / "video.json").read_bytes())
        steps = [json.loads(line) for line in (folder / "trajectory.jsonl").read_text().splitlines()]
        assert info.started_at <= steps[0]["started_at"]
        assert info.started_at + info.duration_s >= steps[-1]["started_at"]
        frames = list(av.open(io.BytesIO((folder / "video.mp4").read_bytes())).decode(video=0))
        assert len(frames) == info.frames >= 2
        assert (frames[0].width, frames[0].height) == (1280, 720)

    # A run may turn the video off (or on) when it resumes: the sweep is the same, nothing is left to run.
    code, out = run_here(write_config(tmp_path, "filmed"), "--progress", "none")
    assert code == 0, out

    site = ViewerSite([tmp_path / "filmed"])
    primitive = next(row for row in rows if row.mode == "primitive")
    page = site.get(f"runs/0/jobs/{primitive.job_id}.html")
    assert page is not None and page.body is not None
    html = page.body.decode()
    folder = str(primitive.artifact_dir).removeprefix("artifacts/")
    assert f'<video controls preload="metadata" src="../files/{folder}/video.mp4">' in html
    assert '<script src="../../../static/video.js">' in html
    marks = json.loads(html.split('<script type="application/json" class="video-marks-data">')[1].split("</script>")[0])
    assert len(marks) == primitive.steps
    assert any("path" in mark for mark in marks) and any("point" in mark for mark in marks)
    served = site.get(f"runs/0/files/{folder}/video.mp4")
    assert served is not None and served.content_type == "video/mp4"

    summary = export_site(site, tmp_path / "export")
    exported = sorted((tmp_path / "export").rglob("video.mp4"))
    assert len(exported) == 2 and summary.files >= 2
    assert (tmp_path / "export" / "static" / "video.js").is_file()
