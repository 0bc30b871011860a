"""``scratchworld oracle-plan``: composite trajectories planned from each task's initial and golden projects."""

from __future__ import annotations

import asyncio
from pathlib import Path
from statistics import mean
from typing import TYPE_CHECKING

import click
from rich.markup import escape
from rich.table import Table
from rich.text import Text

from scratchworld_dist._console import make_console
from scratchworld_dist.cli._options import tasks_option
from scratchworld_dist.suites import CATEGORIES

if TYPE_CHECKING:
    from scratchworld_dist.kinds.tasks.oracle_plan import TaskPlanRecord

EXIT_NOT_EXPRESSED = 1


def render_totals(records: list[TaskPlanRecord]) -> Table:
    """Per category and overall: tasks, reached and replayed, and mean length and modified blocks."""
    table = Table("category", "tasks", "reached golden", "replayed", "mean calls", "mean modified blocks")
    groups = [(c, [r for r in records if r.category == c]) for c in CATEGORIES] + [("all", records)]
    for name, rows in groups:
        planned = [r for r in rows if r.error is None]
        if not rows:
            continue
        table.add_row(
            name,
            str(len(rows)),
            str(sum(r.reached_golden for r in rows)),
            str(sum(r.replayed for r in rows)),
            f"{mean(r.actions for r in planned):.1f}" if planned else "-",
            f"{mean(r.modified_blocks for r in planned):.2f}" if planned else "-",
        )
    return table


@click.command(
    "oracle-plan", epilog="Example: scratchworld oracle-plan ../scratchworld-upstream --out plans --tasks a,b"
)
@click.argument("suite_dir", type=click.Path(file_okay=False, path_type=Path))
@tasks_option
@click.option(
    "--out",
    required=True,
    type=click.Path(file_okay=False, path_type=Path),
    help="Folder for <task_id>.json and plans.json (never inside the suite).",
)
def oracle_plan_command(suite_dir: Path, task_ids: list[str] | None, out: Path) -> None:
    """Plan a composite trajectory from each task's initial project to its golden project.

    Each plan is made on a live editor through the composite API itself, then replayed on a fresh
    load and compared with the golden by structure (opcodes, fields, literals, nesting; not ids or
    positions). An upstream clone needs only its projects. Give OUT as `oracle_trajectories:` of a
    sweep config and the oracle agent replays these (composite) or acts them out (primitive) for
    tasks that ship no trajectory. Exits 1 when a task's golden cannot be reached, naming what the
    API lacks.
    """
    from scratchworld_dist.kinds.tasks.oracle_plan import (  # the browser stack: here only
        plan_folder,
        plan_suite,
        planning_suite,
    )

    suite = planning_suite(suite_dir)
    tasks = suite.select(ids=task_ids)
    folder = plan_folder(out, suite)
    console = make_console(stderr=True)
    console.print(f"planning {len(tasks)} task(s) of {suite.name} into {folder}", markup=False)

    def shown(record: TaskPlanRecord) -> None:
        if record.error is not None:
            console.print(f"  {record.task_id}: [red]error[/red] {escape(record.error)}")
            return
        state = "reached" if record.reached_golden else "[yellow]not reached[/yellow]"
        replay = "" if record.replayed else ", [red]replay differs[/red]"
        console.print(
            f"  {escape(record.task_id)}: {record.actions} call(s), {record.modified_blocks} block(s) modified, "
            f"{state}{replay} ({record.seconds:.1f}s)"
        )
        for lack in record.lacks:
            console.print(Text(f"      {lack}"), highlight=False)

    plans = asyncio.run(plan_suite(suite, tasks, folder, on_task=shown))
    make_console().print(render_totals(plans.tasks))
    failed = [r for r in plans.tasks if r.error is not None or not r.reached_golden or not r.replayed]
    if failed:
        console.print(f"[yellow]{len(failed)} of {len(plans.tasks)} task(s) not fully expressed[/yellow]")
        raise click.exceptions.Exit(EXIT_NOT_EXPRESSED)
    console.print(f"all {len(plans.tasks)} task(s) planned and replayed to their golden")
