"""``validate`` from a stated seed: each task's golden and initial draw the random numbers of its jobs at that
sweep seed, and the rows say which seed that was."""

from __future__ import annotations

import pytest

from scratchworld_dist import load_suite, validate_tasks
from tests.conftest import REPO
from workers.contract import evaluation_seed

TASKS = ["sum_two_numbers", "star_shower"]


@pytest.mark.browser
async def test_validate_draws_from_the_stated_sweep_seed_and_records_it() -> None:
    tasks = load_suite(REPO / "tasks").select(ids=TASKS)
    for seed in (0, 3):
        rows = await validate_tasks(tasks, seed=seed)
        for row in rows:
            assert row.golden is not None and row.golden.success
            wanted = evaluation_seed(row.task_id, seed)
            assert (row.golden.random_seed, row.initial.random_seed) == (wanted, wanted)
