"""Prints how long `scratchworld view` takes to open a large run: a synthetic run of N jobs (default 10,000).

    .venv/bin/python benchmarks/viewer.py [--jobs 10000] [--keep DIR]

The run is written like a sweep writes one (compacted Parquet shards, a manifest; each job with
steps and tests rows; four models, two modes, the 12 tasks of our suite, seeds; some errors and
retries). Then, on the viewer's local server in a real Chromium, it times:

- the runs page, the run page (report tables and plots) and the jobs table until its first page of
  rows is drawn (data loaded, filters filled), each from navigation start;
- filtering the jobs table to failed primitive jobs (one user action, until the counts update);
- one job's page.

The target is under 2 s for the jobs table of a 10,000-job run.
"""

from __future__ import annotations

import argparse
import asyncio
import random
import shutil
import tempfile
import time
from datetime import UTC, datetime, timedelta
from pathlib import Path

from playwright.async_api import Page, async_playwright

from scratchworld_dist.results import (
    SCHEMA_VERSION,
    JobRecord,
    JobRow,
    RunManifest,
    RunStore,
    StepRow,
    TestRow,
    write_manifest,
)
from scratchworld_dist.suites import load_suite
from scratchworld_dist.sweep import SuiteInfo
from scratchworld_dist.viewer import ViewerSite
from scratchworld_dist.viewer._server import serve
from workers.contract import HarnessFingerprint
from workers.node import default_chromium

REPO = Path(__file__).resolve().parents[1]
HARNESS = HarnessFingerprint(digest="bench0000viewer0", parts={})
MODELS = ("gpt-5", "claude-sonnet-4.5", "gemini-2.5-pro", "qwen3-vl")


def synthetic_run(folder: Path, jobs: int) -> Path:
    """A run directory of ``jobs`` jobs (and their steps and tests), compacted as a finished sweep leaves it."""
    tasks = load_suite(REPO / "tasks").tasks
    rng = random.Random(0)
    store = RunStore(folder)
    store.open_for_writing()
    start = datetime(2026, 11, 1, tzinfo=UTC)
    for n in range(jobs):
        task, model, mode = (
            tasks[n % len(tasks)],
            MODELS[n // len(tasks) % len(MODELS)],
            ("composite", "primitive")[n % 2],
        )
        seed = n // (len(tasks) * len(MODELS) * 2)
        for attempt in (1, 2) if n % 97 == 0 else (1,):
            outcome = "error" if attempt == 1 and n % 97 == 0 else rng.choice(("passed", "failed", "failed"))
            record = _record(f"{n:024x}", attempt, task.id, task.category, model, mode, seed, outcome, start, n, rng)
            store.commit(record)
    store.close()
    planned = jobs
    manifest = RunManifest(
        run_name="bench-viewer",
        schema_version=SCHEMA_VERSION,
        harness=HARNESS,
        config={"name": "bench-viewer", "episodes": {"modes": ["composite", "primitive"]}},
        config_hash="bench",
        suite=SuiteInfo(name="scratchworld-dist-core", kind="native", root=str(REPO / "tasks"), hash="s", tasks=12),
        planned_jobs=planned,
    )
    write_manifest(folder, manifest)
    return folder


def _record(
    job_id: str,
    attempt: int,
    task_id: str,
    category: str,
    model: str,
    mode: str,
    seed: int,
    outcome: str,
    start: datetime,
    n: int,
    rng: random.Random,
) -> JobRecord:
    steps = rng.randint(3, 40)
    decided = outcome != "error"
    passed = 3 if outcome == "passed" else rng.randint(0, 2) if decided else 0
    row = JobRow(
        run_name="bench-viewer",
        job_id=job_id,
        attempt=attempt,
        model=model,
        litellm_model=f"openai/{model}",
        mode=mode,
        agent="llm",
        task_id=task_id,
        category=category,
        task_hash="t",
        suite_hash="s",
        seed=seed,
        max_steps=100,
        harness_fingerprint=HARNESS.digest,
        outcome=outcome,
        error_class=None if decided else "model_rate_limited",
        error_message=None if decided else "429 from the provider",
        eval_error_kind=None,
        eval_profile="native" if decided else None,
        stop_reason="done" if decided else "model_rate_limited",
        tests_passed=passed,
        tests_total=3 if decided else 0,
        psr=passed / 3 if decided else None,
        steps=steps,
        llm_calls=steps,
        input_tokens=steps * 3000,
        output_tokens=steps * 200,
        cost_usd=steps * 0.004,
        episode_s=steps * 4.0,
        setup_s=2.0,
        agent_s=steps * 3.8,
        evaluation_s=1.0,
        started_at=start + timedelta(seconds=n * 3),
        finished_at=start + timedelta(seconds=n * 3 + steps * 4),
        worker_node="node",
        worker_host="host",
        worker_pid=1,
        worker_index=n % 8,
        artifact_dir=None,
    )
    step_rows = [
        StepRow(
            job_id=job_id,
            attempt=attempt,
            step=i,
            action="add_block",
            args_json='{"blockType": "motion_movesteps"}',
            ok=i % 7 != 3,
            error_code=None if i % 7 != 3 else "UNKNOWN_BLOCK",
            error_message=None if i % 7 != 3 else "no such block",
            latency_s=3.8,
            observation_s=0.2,
            warnings=None,
            llm_calls=1,
            input_tokens=3000,
            output_tokens=200,
            cost_usd=0.004,
        )
        for i in range(steps)
    ]
    tests = [
        TestRow(
            job_id=job_id,
            attempt=attempt,
            task_id=task_id,
            test_index=i,
            name=f"test {i}",
            passed=i < passed,
            error=None if i < passed else "expected 7, got 0",
            duration_ms=12.0,
        )
        for i in range(3 if decided else 0)
    ]
    return JobRecord(job=row, steps=step_rows, tests=tests)


async def timed(page: Page, url: str, ready: str) -> float:
    started = time.perf_counter()
    await page.goto(url)
    await page.wait_for_selector(ready, state="attached")
    return time.perf_counter() - started


async def measure(run: Path) -> None:
    announced: asyncio.Future[str] = asyncio.get_running_loop().create_future()
    server = asyncio.create_task(serve(ViewerSite([run]), 0, announced.set_result))
    root = await announced
    async with async_playwright() as playwright:
        browser = await playwright.chromium.launch(executable_path=str(default_chromium()))
        page = await browser.new_page(viewport={"width": 1400, "height": 1000})
        print(f"runs page        {await timed(page, root, 'table.runs'):.2f} s")
        print(f"run page         {await timed(page, root + 'runs/0/index.html', 'h2'):.2f} s (report and plots)")
        print(f"jobs table       {await timed(page, root + 'runs/0/jobs.html', '#jobs[data-ready=true]'):.2f} s")
        print(f"jobs table again {await timed(page, root + 'runs/0/jobs.html', '#jobs[data-ready=true]'):.2f} s")
        started = time.perf_counter()
        await page.select_option("select[data-column=outcome]", "failed")
        await page.select_option("select[data-column=mode]", "primitive")
        counts = await page.locator("#counts").inner_text()
        print(f"filter           {time.perf_counter() - started:.2f} s ({counts})")
        first = page.locator("#jobs tbody tr a").first
        href = await first.get_attribute("href")
        print(f"job page         {await timed(page, root + 'runs/0/' + str(href), '#outcome'):.2f} s")
        await browser.close()
    server.cancel()
    await asyncio.gather(server, return_exceptions=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--jobs", type=int, default=10_000)
    parser.add_argument("--keep", type=Path, help="write the synthetic run here and keep it")
    args = parser.parse_args()
    folder = args.keep or Path(tempfile.mkdtemp(prefix="bench-viewer-"))
    try:
        started = time.perf_counter()
        synthetic_run(folder, args.jobs)
        print(f"synthetic run of {args.jobs} jobs written in {time.perf_counter() - started:.1f} s -> {folder}")
        asyncio.run(measure(folder))
    finally:
        if args.keep is None:
            shutil.rmtree(folder, ignore_errors=True)


if __name__ == "__main__":
    main()
