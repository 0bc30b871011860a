"""The viewer marks tests known to be unstable: a badge with the test's note on the job page, a line naming the
tasks with unstable tests on the run page; a run without stability data shows neither."""

from __future__ import annotations

from pathlib import Path

from markupsafe import escape

from scratchworld_dist.viewer import ViewerSite
from tests.support.unstable_runs import BEAT_NOTE, HOSTILE, HOSTILE_NOTE, WEAK, marked_run


def _page(site: ViewerSite, path: str) -> str:
    page = site.get(path)
    assert page is not None and page.body is not None, path
    return page.body.decode()


def test_job_pages_mark_unstable_tests_with_their_note_and_the_run_page_names_their_tasks(tmp_path: Path) -> None:
    site = ViewerSite([marked_run(tmp_path / "run", WEAK, model="gpt")])
    beat = _page(site, "runs/0/jobs/t1-0-gpt.html")
    badge = f'<span class="badge unstable" title="{escape(BEAT_NOTE)}">unstable</span>'
    assert f"<td>moves on the beat {badge}</td>" in beat
    assert "<td>score shown</td>" in beat  # the stable test beside it is not marked
    hostile = _page(site, "runs/0/jobs/t4-0-gpt.html")
    assert f'<td>{escape(HOSTILE)} <span class="badge unstable" title="{escape(HOSTILE_NOTE)}">' in hostile
    assert "<b>only</b>" not in hostile and "<script>" not in hostile
    assert "badge unstable" not in _page(site, "runs/0/jobs/t2-0-gpt.html")
    run_page = _page(site, "runs/0/index.html")
    assert "Tasks with tests known to be unstable" in run_page and ": t1 (1 test), t4 (1 test)." in run_page


def test_a_run_without_stability_data_marks_nothing(tmp_path: Path) -> None:
    site = ViewerSite([marked_run(tmp_path / "run", WEAK, model="gpt", marks=None)])
    assert "unstable" not in _page(site, "runs/0/jobs/t1-0-gpt.html")
    assert "unstable" not in _page(site, "runs/0/index.html").lower()
