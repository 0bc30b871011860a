"""``scratchworld drag``: the single-step drag benchmark's own tools (running it is ``scratchworld run``
with ``benchmark: drag``)."""

from __future__ import annotations

import asyncio
import json
from pathlib import Path

import click

from scratchworld_dist.cli._options import tasks_option

EXIT_INVALID = 1


@click.group("drag", epilog="Example: scratchworld drag make projects/*.sb3 --out drag-tasks --per-project 5")
def drag_group() -> None:
    """Single-step drag tasks: generate a suite from projects, validate a suite in this editor."""


@drag_group.command("make", epilog="Example: scratchworld drag make projects/*.sb3 --out drag-tasks --per-project 5")
@click.argument("projects", nargs=-1, required=True, type=click.Path(exists=True, dir_okay=False, path_type=Path))
@click.option("--out", required=True, type=click.Path(file_okay=False, path_type=Path), help="New suite folder.")
@click.option("--name", default=None, help="Suite name (default: the folder's name).")
@click.option("--per-project", type=click.IntRange(min=1), default=None, help="Tasks kept per project (balanced).")
@click.option("--seed", type=int, default=0, show_default=True, help="Seed of the balanced selection.")
def make_command(projects: tuple[Path, ...], out: Path, name: str | None, per_project: int | None, seed: int) -> None:
    """Make drag tasks from PROJECTS (.sb3): every connection of every script can be detached and asked back.

    Each candidate is framed in a real editor and kept only if the oracle passes it there; what is
    left out is listed with its reason.
    """
    from scratchworld_dist.kinds.drag.items import make_drag_suite  # the browser stack, for this command only

    made = asyncio.run(
        make_drag_suite(
            list(projects),
            out,
            name=name or out.name,
            per_project=per_project,
            seed=seed,
            on_problem=lambda message: click.echo(f"left out: {message}", err=True),
        )
    )
    click.echo(f"wrote {made.tasks} drag task(s) of {made.candidates} candidate(s) to {made.root}")


@drag_group.command("validate", epilog="Example: scratchworld drag validate drag-tasks --tasks a,b --parallel 2")
@click.argument("suite_dir", type=click.Path(file_okay=False, path_type=Path))
@tasks_option
@click.option("--parallel", type=click.IntRange(min=1), default=1, show_default=True, help="Editors at a time.")
@click.option(
    "--json", "json_file", type=click.Path(dir_okay=False, path_type=Path), help="Write each task's check and regions."
)
def validate_command(suite_dir: Path, task_ids: list[str] | None, parallel: int, json_file: Path | None) -> None:
    """Check every drag task of SUITE_DIR in this editor: its exact regions, and the oracle's drag through them.

    A task is valid when its view sets up, its regions are not empty and a real drag from the start
    region's deepest pixel to the end region's makes the expected connection. Exits 1 when a task is
    invalid or cannot be set up.
    """
    from scratchworld_dist._console import make_console  # rich: for this command only
    from scratchworld_dist.kinds.drag.items import DragTaskCheck, load_drag_suite, validate_drag_tasks

    suite = load_drag_suite(suite_dir)
    wanted = task_ids
    tasks = [suite.task(task_id) for task_id in wanted] if wanted else list(suite.tasks)
    console = make_console(stderr=True)
    for problem in suite.problems:
        console.print(f"{problem.effect}: {problem}", markup=False)
    viewless = [task.id for task in tasks if task.view is None]
    ready = [task for task in tasks if task.view is not None]
    console.print(f"validating {len(ready)} drag task(s) of {suite.name} ({suite.kind}) with {parallel} editor(s)")

    def progress(check: DragTaskCheck) -> None:
        areas = f"start {check.regions.start.area} px, end {check.regions.end.area} px" if check.regions else "-"
        verdict = "ok" if check.valid else f"INVALID: {check.detail}"
        console.print(f"  {check.task_id} ({check.connection}, {check.source}): {areas}; {verdict}", markup=False)

    checks = asyncio.run(validate_drag_tasks(ready, editors=parallel, on_checked=progress))
    if json_file is not None:
        rows = ",\n".join(json.dumps(check.model_dump(mode="json")) for check in checks)  # a task a line
        json_file.write_text(f"[\n{rows}\n]\n", encoding="utf-8")
    invalid = [check for check in checks if not check.valid]
    if invalid or viewless:
        unset = f"; {len(viewless)} without a view: {', '.join(viewless)}" if viewless else ""
        console.print(f"{len(invalid)} of {len(checks)} drag task(s) invalid{unset}", markup=False)
        raise click.exceptions.Exit(EXIT_INVALID)
    console.print(f"all {len(checks)} drag task(s) valid")
