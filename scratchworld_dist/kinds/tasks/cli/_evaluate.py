"""``scratchworld evaluate``: one project against one task."""

from __future__ import annotations

import asyncio
from pathlib import Path

import click
from rich.console import Console
from rich.markup import escape
from rich.table import Table
from rich.text import Text

from scratchworld_dist._console import make_console
from scratchworld_dist._files import read_file
from scratchworld_dist.cli._options import evaluation_seed_option, page_option, render_option, timing_option
from scratchworld_dist.suites import UnstableTest, known_stability, load_suite
from workers.contract import (
    MIB,
    EvalResult,
    EvaluationClock,
    EvaluationPage,
    EvaluationProfile,
    EvaluationRender,
    EvaluationSpec,
    EvaluationTiming,
    ProjectLimits,
)

EXIT_NOT_PASSED = 1
EXIT_NO_VERDICT = 3


async def _evaluate(project: bytes, spec: EvaluationSpec) -> EvalResult:
    # The browser stack loads with the command that needs it: ``report`` and ``status`` never do.
    from workers.editor import BrowserSession
    from workers.evaluation import Evaluator

    async with BrowserSession() as session:
        return await Evaluator(session).evaluate(project, spec)


def read_project_file(path: Path) -> bytes:
    """The bytes of a project file named on the command line, read no further than the project limit."""
    return read_file(path, int(ProjectLimits().max_file_mb * MIB))


def render_result(result: EvalResult, console: Console, unstable: dict[str, UnstableTest] | None = None) -> None:
    """The verdict, tests known to be unstable marked (``unstable``: the task's, by name); what the script or
    project wrote is shown as text, never read as markup."""
    table = Table("test", "passed", "note")
    for test in result.tests:
        known = (unstable or {}).get(test.name)
        note = " ".join(part for part in (test.error or "", known.note() if known else "") if part)
        table.add_row(Text(test.name), "yes" if test.passed else "no", Text(note))
    if result.tests:
        console.print(table)
    if result.conditions is not None:
        c = result.conditions
        console.print(
            f"profile {c.profile}: stage canvas {c.stage_canvas[0]}x{c.stage_canvas[1]}, mouse known {c.mouse_known}; "
            f"clock {c.clock}; render {c.render}; page {c.page}; timing {c.timing}"
        )
    if result.error:
        # One line whatever the terminal's width, so logs and pipes keep the cause whole.
        console.print(f"[red]no verdict[/red] ({result.error.kind}): {escape(result.error.message)}", soft_wrap=True)
    else:
        console.print(
            f"passed {result.passed}/{result.total} (PSR {result.psr:.2f}): {'SUCCESS' if result.success else 'FAIL'}"
        )
    for warning in result.warnings:
        console.print(f"[yellow]warning[/yellow]: {escape(warning)}", soft_wrap=True)


@click.command(
    "evaluate", epilog="Example: scratchworld evaluate tasks sum_two_numbers my_project.sb3 --json result.json"
)
@click.argument("suite_dir", type=click.Path(file_okay=False, path_type=Path))
@click.argument("task_id")
@click.argument("project", type=click.Path(exists=True, dir_okay=False, path_type=Path))
@click.option(
    "--json", "json_file", type=click.Path(dir_okay=False, path_type=Path), help="Write the EvalResult as JSON."
)
@click.option("--profile", type=click.Choice(["native", "upstream"]), help="Evaluation profile (default: the suite's).")
@click.option("--clock", type=click.Choice(["virtual", "real"]), help="Evaluation clock (default: the suite's).")
@render_option
@page_option
@timing_option
@evaluation_seed_option
def evaluate_command(
    suite_dir: Path,
    task_id: str,
    project: Path,
    json_file: Path | None,
    profile: EvaluationProfile | None,
    clock: EvaluationClock | None,
    render: EvaluationRender | None,
    page: EvaluationPage | None,
    timing: EvaluationTiming | None,
    seed: int,
) -> None:
    """Evaluate PROJECT (.sb3) against TASK_ID of the suite in SUITE_DIR.

    Exit status: 0 all tests passed, 1 some failed, 3 no verdict (the evaluation itself failed, or
    PROJECT is not a loadable project), 2 unusable arguments (e.g. a PROJECT file over the project
    size limit, or not a regular file).
    """
    suite = load_suite(suite_dir)
    task = suite.task(task_id)
    spec = task.evaluation_spec(profile, clock, render, timing, page=page, seed=seed)
    known = known_stability(suite)
    data = read_project_file(project)
    # A project no page may see is refused here, naming the file, before a browser starts.
    from workers.evaluation import project_refusal

    result = project_refusal(data, ProjectLimits(), name=str(project)) or asyncio.run(_evaluate(data, spec))
    render_result(result, make_console(), known.unstable_tests(task) if known is not None else None)
    if json_file is not None:
        json_file.write_text(result.model_dump_json(indent=2) + "\n", encoding="utf-8")
    if result.error is not None:
        raise click.exceptions.Exit(EXIT_NO_VERDICT)
    if not result.success:
        raise click.exceptions.Exit(EXIT_NOT_PASSED)
