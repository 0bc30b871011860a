"""On upstream's own scripts, unchanged, a mutant judged to its first failing test gets the verdict every test
gives it: the same tests fail up to the one that stopped it, and that one is the first that fails in the full
run. Tasks are picked by their script being present (every tenth, in the suite's order), never by id; without
``../shared`` the test skips."""

from __future__ import annotations

import io
import json
import zipfile
from pathlib import Path

import pytest

from scratchworld_dist.kinds.audit.variants import sample_mutants
from scratchworld_dist.kinds.tasks import read_task
from scratchworld_dist.sb3 import Sb3Archive
from scratchworld_dist.suites import UpstreamSuiteLoader
from workers.contract import EvalResult
from workers.evaluation import Evaluator

pytestmark = [pytest.mark.browser, pytest.mark.slow, pytest.mark.upstream]


def verdict(result: EvalResult) -> tuple[bool, str | None]:
    return result.success, result.error.kind if result.error else None


async def test_upstream_mutants_get_the_same_verdict_when_their_tests_stop_early(
    upstream_dir: Path, evaluator: Evaluator
) -> None:
    suite = UpstreamSuiteLoader(require_scripts=False).load(upstream_dir)
    tasks = [task for task in suite.tasks if task.evaluation_script.is_file() and task.golden_project is not None]
    if not tasks:
        pytest.skip(f"no evaluation scripts under {upstream_dir}")
    stops = 0
    for task in tasks[::10]:
        content = read_task(task)
        golden = content.payload.golden_project
        assert golden is not None
        with zipfile.ZipFile(io.BytesIO(golden)) as archive:
            project = json.loads(archive.read("project.json"))
        stopping = content.payload.evaluation.model_copy(update={"stop_at_first_failure": True})
        for mutant in sample_mutants(project, 2, f"0:{task.id}"):
            sb3 = Sb3Archive(golden).with_project(mutant.project)
            full = await evaluator.evaluate(sb3, content.payload.evaluation)
            stopped = await evaluator.evaluate(sb3, stopping)
            where = f"{task.id} {mutant.change}"
            assert verdict(stopped) == verdict(full), where
            early = stopped.stopped_early
            if early is None:
                continue
            stops += 1
            ran = [(test.name, test.passed) for test in stopped.tests]
            assert ran == [(test.name, test.passed) for test in full.tests][: len(ran)], where
            assert ran[-1] == (early.test, False) and stopped.total == full.total, where
            assert len(ran) + early.not_run == len(full.tests), where
    assert stops > 0  # the sample holds killed mutants with tests left after their killer
