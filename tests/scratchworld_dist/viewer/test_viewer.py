"""`scratchworld view`: a real run of our suite by the LLM agent (a local OpenAI-compatible server scripts
the model), served on 127.0.0.1 and exported, driven in our Chromium like a user would.

The scripted model solves quiz_score in composite mode from its golden trajectory, asks for a block
that does not exist on sum_two_numbers (an error envelope) and gives up, and in primitive mode drags a
palette block onto the canvas, clicks the Variables category and says done: so the run holds passed
and failed jobs, an error envelope, and primitive steps with screenshots and gestures to draw.
"""

from __future__ import annotations

import asyncio
import json
import re
from collections.abc import AsyncIterator, Iterator
from pathlib import Path
from typing import Any

import pytest
import yaml
from playwright.async_api import Browser, Page, async_playwright

from scratchworld_dist.results import JobRecord, RunStore
from scratchworld_dist.suites import load_suite
from scratchworld_dist.viewer import ViewerSite, export_site
from scratchworld_dist.viewer._server import serve
from tests.conftest import REPO
from tests.support.cli_runner import invoke
from tests.support.openai_server import Behaviour, OpenAIServer, reply
from tests.support.projects import counter_project
from tests.support.run_dirs import drag_record, job, make_run, regrade_run
from tests.support.sweep_driver import run_here
from workers.node import default_chromium

SOLVED, FUMBLED = "quiz_score", "sum_two_numbers"


def answer(action: dict[str, Any]) -> str:
    return f"Analysis: the next step of my plan.\n```json\n{json.dumps(action)}\n```"


class ScriptedModel:
    """Answers from the conversation alone (see the module's docstring)."""

    def __init__(self) -> None:
        suite = load_suite(REPO / "tasks")
        self.golden = suite.task(SOLVED).trajectory() or []
        self.solved_instruction = suite.task(SOLVED).instruction

    def __call__(self, body: dict[str, Any]) -> Behaviour:
        messages = body["messages"]
        system = messages[0]["content"]
        turn = sum(1 for m in messages if m["role"] == "assistant")
        if "drag_and_drop" in system:  # primitive mode
            text = next(p["text"] for p in messages[-1]["content"] if p["type"] == "text")
            if turn == 0:
                block = re.search(r"^(\d+)  blocks  ", text, re.M)
                assert block is not None, text[:2000]
                return reply(
                    answer({"api": "drag_and_drop", "args": {"start_index": int(block[1]), "end_x": 760, "end_y": 420}})
                )
            if turn == 1:
                variables = re.search(r"^(\d+)  category_menu_item  Variables ", text, re.M)
                assert variables is not None
                return reply(answer({"api": "click", "args": {"index": int(variables[1])}}))
            return reply(answer({"api": "done", "args": {}}))
        if self.solved_instruction in system:
            if turn < len(self.golden):
                return reply(answer(self.golden[turn].model_dump(mode="json", include={"api", "args"})))
            return reply(answer({"api": "done", "args": {}}))
        if turn == 0:
            return reply(answer({"api": "add_block", "args": {"blockType": "motion_fly_to_the_moon"}}))
        return reply(answer({"api": "done", "args": {}}))


@pytest.fixture(scope="module")
def model_server() -> Iterator[OpenAIServer]:
    """The scripted model, and its address in the environment before the module's Ray starts (its workers
    read the variables the config names)."""
    with OpenAIServer(responder=ScriptedModel()) as server, pytest.MonkeyPatch.context() as env:
        env.setenv("SCRATCHWORLD_LLM_BASE_URL", server.url)
        env.setenv("SCRATCHWORLD_LLM_API_KEY", "sk-viewer-test-5c1d")
        yield server


@pytest.fixture(scope="module")
def llm_run(tmp_path_factory: pytest.TempPathFactory, model_server: OpenAIServer, shared_ray: int) -> Path:
    folder = tmp_path_factory.mktemp("viewer")
    model = {"api_base_env": "SCRATCHWORLD_LLM_BASE_URL", "api_key_env": "SCRATCHWORLD_LLM_API_KEY"}
    config = {
        "name": "viewer-demo",
        "suite": str(REPO / "tasks"),
        "tasks": {"ids": [SOLVED, FUMBLED]},
        "agent": "llm",
        "models": [{"model": "openai/gpt-4o-mini", "name": "mini", **model}],
        "episodes": {"modes": ["composite", "primitive"], "max_steps": 40},
        "primitive": {"ocr": "none"},
        "llm": {"history_messages": 200, "retry": {"max_attempts": 2, "initial_backoff_s": 0.05}},
        "limits": {"retries": 1, "episode_timeout_s": 240},
        "output": str(folder / "run"),
        "probe": False,  # the scripted model answers episodes only (the probe: tests/.../scheduling/test_preflight.py)
    }
    path = folder / "viewer.yaml"
    path.write_text(yaml.safe_dump(config))
    code, log = run_here(path)
    assert code == 0, log  # failed jobs are verdicts: the run itself went through
    outcomes = {(r.task_id, r.mode): r.outcome for r in RunStore(folder / "run").job_rows()}
    assert outcomes == {
        (SOLVED, "composite"): "passed",
        (FUMBLED, "composite"): "failed",
        (SOLVED, "primitive"): "failed",
        (FUMBLED, "primitive"): "failed",
    }
    return folder / "run"


@pytest.fixture(scope="module")
async def viewer_browser() -> AsyncIterator[Browser]:
    """A plain Chromium, as a user's: the editor's sessions send every request through the editor server."""
    async with async_playwright() as playwright:
        browser = await playwright.chromium.launch(executable_path=str(default_chromium()))
        yield browser
        await browser.close()


@pytest.fixture
async def page(viewer_browser: Browser) -> AsyncIterator[Page]:
    context = await viewer_browser.new_context(viewport={"width": 1400, "height": 1000})
    try:
        yield await context.new_page()
    finally:
        await context.close()


@pytest.fixture
async def served(llm_run: Path) -> AsyncIterator[str]:
    announced: asyncio.Future[str] = asyncio.get_running_loop().create_future()
    task = asyncio.create_task(serve(ViewerSite([llm_run]), 0, announced.set_result))
    try:
        yield await asyncio.wait_for(announced, 30)
    finally:
        task.cancel()
        await asyncio.gather(task, return_exceptions=True)


def requests_of(page: Page) -> list[str]:
    urls: list[str] = []
    page.on("request", lambda request: urls.append(request.url))
    return urls


async def open_failed_job(page: Page, root: str, mode: str) -> None:
    """From the runs page to the jobs table, filtered to failed jobs of ``mode``, to the first one's page."""
    await page.goto(root + "index.html")
    await page.get_by_role("link", name="jobs").first.click()
    await page.wait_for_selector("#jobs[data-ready=true]")
    assert (await page.locator("#counts").inner_text()).startswith("4 of 4 jobs")
    await page.select_option("select[data-column=outcome]", "failed")
    await page.select_option("select[data-column=mode]", mode)
    expected = "2 of 4 jobs · failed 2" if mode == "primitive" else "1 of 4 jobs · failed 1"
    assert await page.locator("#counts").inner_text() == expected
    assert "outcome=failed" in page.url  # the selection is in the link
    await page.locator("#jobs tbody tr a").first.click()
    await page.wait_for_selector("#outcome")
    assert await page.locator("#outcome").inner_text() == "failed"


@pytest.mark.browser
@pytest.mark.ray
@pytest.mark.slow
async def test_a_user_filters_to_a_failed_job_and_reads_its_steps_envelope_and_tests(page: Page, served: str) -> None:
    urls = requests_of(page)
    await open_failed_job(page, served, "composite")
    assert FUMBLED in await page.locator("h1").inner_text()
    envelope = page.locator("li.step.failed .envelope.error").first
    assert "motion_fly_to_the_moon" in await envelope.inner_text()
    assert await page.locator("li.step").count() == 2
    assert "the next step of my plan" in await page.locator("blockquote.analysis").first.inner_text()
    # The observation the model was shown, and the tests with their verdicts.
    assert "Current Editing Target" in await page.locator("pre.observation-text").first.inner_text()
    tests = page.locator("table.tests tbody tr")
    assert await tests.count() >= 1
    assert await page.locator("table.tests tbody tr.fail").count() >= 1
    assert "== Sprite:" in await page.locator("pre.listing").inner_text()
    assert all(url.startswith(served) for url in urls), urls


@pytest.mark.browser
@pytest.mark.ray
@pytest.mark.slow
async def test_a_primitive_step_shows_its_screenshot_with_the_gesture_drawn(page: Page, served: str) -> None:
    await open_failed_job(page, served, "primitive")
    drag, click = page.locator("li.step").nth(0), page.locator("li.step").nth(1)
    shot = drag.locator(".shot img")
    await shot.scroll_into_view_if_needed()
    await page.wait_for_function("(img) => img.complete && img.naturalWidth === 1280", arg=await shot.element_handle())
    line = drag.locator("svg.mark g.drag line")
    assert (float(await line.get_attribute("x2") or 0), float(await line.get_attribute("y2") or 0)) == (760, 420)
    assert re.fullmatch(r"drag: (not )?snapped", await drag.locator(".mark-label").inner_text())
    assert await click.locator("svg.mark circle.click").count() == 1
    # Hovering an element of the list shows its label over the screenshot.
    box = drag.locator(".shot .box").first
    await box.hover(force=True)
    assert re.match(r"0  \w+", await box.get_attribute("data-label") or "")


@pytest.mark.browser
@pytest.mark.ray
@pytest.mark.slow
async def test_the_static_export_opens_from_file_with_no_request_leaving_the_machine(
    page: Page, llm_run: Path, tmp_path: Path
) -> None:
    summary = export_site(ViewerSite([llm_run]), tmp_path / "site")
    assert summary.files > 0
    urls = requests_of(page)
    root = (tmp_path / "site").as_uri() + "/"
    await open_failed_job(page, root, "primitive")
    shot = page.locator("li.step .shot img").first
    await shot.scroll_into_view_if_needed()
    await page.wait_for_function("(img) => img.complete && img.naturalWidth === 1280", arg=await shot.element_handle())
    await page.goto(root + "runs/0/index.html")
    assert await page.locator("section.sw-plots svg").count() >= 1
    assert urls and all(url.startswith("file://") for url in urls), [u for u in urls if not u.startswith("file://")]


def hand_made(tmp_path: Path) -> Path:
    hostile = "<script>alert(1)</script>"
    rows = [
        job("job-passed", task_id="t1"),
        job("job-hostile", "failed", task_id=hostile, model=hostile, error_message=hostile),
        job("job-error", "error", task_id="t3"),
    ]
    return make_run(tmp_path / "run", rows, planned=4, tasks=3)


def test_pages_escape_what_runs_hold_and_refuse_paths_outside_them(tmp_path: Path) -> None:
    site = ViewerSite([hand_made(tmp_path)])
    job_page = site.get("runs/0/jobs/job-hostile.html")
    assert job_page is not None and job_page.body is not None
    assert b"<script>alert(1)</script>" not in job_page.body
    assert b"&lt;script&gt;alert(1)&lt;/script&gt;" in job_page.body
    data = site.get("runs/0/jobs-data.js")
    assert data is not None and data.body is not None
    assert b"</script>" not in data.body  # JSON with \u003c: and the table writes cells as text
    rows = json.loads(data.body.decode().removeprefix("window.scratchworldJobs = ").rstrip(";\n"))["rows"]
    assert len(rows) == 3
    for path in (
        "runs/0/files/../manifest.json",
        "runs/0/files/%2e%2e/manifest.json",
        "runs/1/index.html",
        "runs/0/jobs/nope.html",
        "static/../_site.py",
        "compare/0-1.html",
        "../etc/passwd",
    ):
        assert site.get(path) is None, path


def test_errors_by_class_link_to_the_filtered_jobs_and_a_run_in_progress_shows_its_jobs(tmp_path: Path) -> None:
    run = hand_made(tmp_path)
    page = ViewerSite([run]).get("runs/0/index.html")
    assert page is not None and page.body is not None
    assert b'href="jobs.html#outcome=error&amp;error_class=EditorCrashedError"' in page.body
    # A journal not yet compacted (a run in progress) is read as well.
    store = RunStore(run)
    store.open_for_writing()
    store.commit(JobRecord(job=job("job-late", task_id="t4")))
    index = ViewerSite([run]).get("index.html")
    assert index is not None and index.body is not None
    assert b"<td>4 / 4</td>" in index.body
    store.close()


def test_bad_run_directories_and_export_folders_get_one_line_errors(tmp_path: Path) -> None:
    done = invoke("view", str(tmp_path / "missing"))
    assert done.returncode == 2 and done.stderr.count("\n") == 1 and "not a scratchworld run directory" in done.stderr
    run = hand_made(tmp_path)
    (tmp_path / "busy").mkdir()
    (tmp_path / "busy" / "notes.txt").write_text("mine")
    done = invoke("view", str(run), "--export", str(tmp_path / "busy"))
    assert done.returncode == 2 and "not empty" in done.stderr
    assert (tmp_path / "busy" / "notes.txt").read_text() == "mine"
    done = invoke("view", str(run), "--export", str(tmp_path / "out"))
    assert done.returncode == 0, done.stderr
    assert (tmp_path / "out" / "runs" / "0" / "jobs" / "job-passed.html").is_file()
    assert (tmp_path / "out" / "static" / "jobs.js").is_file()
    again = invoke("view", str(run), "--export", str(tmp_path / "out"))  # an earlier export is refreshed
    assert again.returncode == 0, again.stderr


def test_a_regrade_shows_its_source_and_the_verdicts_it_changed(tmp_path: Path) -> None:
    source = make_run(tmp_path / "a", [job(f"t{i}", eval_clock="virtual") for i in range(3)], planned=3, tasks=3)
    regrade = regrade_run(source, tmp_path / "b", {"t1"})
    site = ViewerSite([source, regrade])
    compare = site.get("compare/0-1.html")
    assert compare is not None and compare.body is not None
    text = compare.body.decode()
    assert "<h2>B regrades A</h2>" in text and "1 verdict(s) changed, 2 kept." in text
    assert "<td>t1</td><td>composite</td><td>0</td><td>passed</td><td>failed</td><td>2/2</td><td>1/2</td>" in text
    run_page = site.get("runs/1/index.html")
    assert run_page is not None and run_page.body is not None
    assert f"regrade of</th><td>sweep ({source.resolve()})" in run_page.body.decode()


def test_comparison_pages_are_the_ones_a_run_s_kind_offers(tmp_path: Path) -> None:
    rows = [
        job(f"{mode}-{i}", outcome, mode=mode, task_id=f"t{i}", task_hash=f"h{i}")
        for mode in ("composite", "primitive")
        for i, outcome in enumerate(("passed", "failed"))
    ]
    episodes = make_run(tmp_path / "episodes", rows, planned=4, tasks=2)
    drags = make_run(tmp_path / "drag", [drag_record("a", 0, "passed", suite_hash="d")], planned=1, tasks=1)
    site = ViewerSite([episodes, drags])
    index = site.get("index.html")
    assert index is not None and index.body is not None
    links = re.findall(r'href="(compare/[^"]+)"', index.body.decode())
    assert links == ["compare/0-gap.html"]  # episodes vs drag: no page, as drag runs compare with nothing
    assert "0: episodes: composite vs primitive (reasoning-acting gap)" in index.body.decode()
    gap = site.get("compare/0-gap.html")
    assert gap is not None and gap.body is not None
    text = gap.body.decode()
    assert "<h1>episodes: composite vs primitive</h1>" in text and "<p>A: gpt (run sweep, 2 jobs)" in text
    for missing in ("compare/0-1.html", "compare/1-0.html", "compare/1-gap.html", "compare/0-nothing.html"):
        assert site.get(missing) is None, missing
    assert "compare/0-gap.html" in set(site.page_paths())
    drag_page = site.get("runs/1/index.html")
    assert drag_page is not None and drag_page.body is not None and b"sw-plots" not in drag_page.body


def test_an_export_through_a_symlinked_run_copies_the_final_project_and_lists_its_scripts(tmp_path: Path) -> None:
    folder = tmp_path / "run" / "artifacts" / "job-one" / "attempt-1"
    folder.mkdir(parents=True)
    (folder / "final.sb3").write_bytes(counter_project().to_sb3())
    make_run(tmp_path / "run", [job("job-one", artifact_dir="artifacts/job-one/attempt-1")], planned=1, tasks=1)
    (tmp_path / "link").symlink_to(tmp_path / "run")
    summary = export_site(ViewerSite([tmp_path / "link"]), tmp_path / "out")
    copied = tmp_path / "out" / "runs" / "0" / "files" / "job-one" / "attempt-1" / "final.sb3"
    assert summary.files == 1 and copied.read_bytes() == (folder / "final.sb3").read_bytes()
    page = (tmp_path / "out" / "runs" / "0" / "jobs" / "job-one.html").read_text()
    assert 'href="../files/job-one/attempt-1/final.sb3"' in page
    assert "control_repeat TIMES=&#34;10&#34;" in page and "data_changevariableby VARIABLE=count" in page
