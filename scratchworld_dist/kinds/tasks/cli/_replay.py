"""``scratchworld replay`` and ``scratchworld observe``: composite mode by hand.

``replay`` performs a trajectory of composite actions on a task's initial project, showing each
action's envelope (and, with ``--video``, recording the editor meanwhile), then evaluates the result like
an episode would; ``observe`` prints what a
composite agent would read for every target of a project (handy when writing trajectories).
"""

from __future__ import annotations

import asyncio
import json
from pathlib import Path
from typing import TYPE_CHECKING

import click
from rich.console import Console
from rich.markup import escape

from scratchworld_dist._console import make_console
from scratchworld_dist._errors import ProjectFormatError
from scratchworld_dist.cli._options import evaluation_seed_option
from scratchworld_dist.kinds.tasks.cli._evaluate import (
    EXIT_NO_VERDICT,
    EXIT_NOT_PASSED,
    read_project_file,
    render_result,
)
from scratchworld_dist.suites import load_suite, read_trajectory
from workers.contract import (
    ActionEnvelope,
    CompositeAction,
    EpisodeVideo,
    EvalResult,
    ProjectLimits,
    RecordSettings,
    check_project,
)

if TYPE_CHECKING:
    from workers.editor import Editor


async def _replay(
    project: bytes,
    actions: list[CompositeAction],
    task_spec: object,
    console: Console,
    show_final: bool,
    record: RecordSettings | None = None,
) -> tuple[list[ActionEnvelope], bytes, EvalResult, EpisodeVideo | None]:
    # The browser stack loads with the command that needs it: ``report`` and ``status`` never do.
    from workers import composite
    from workers.editor import BrowserSession, EditorPool
    from workers.evaluation import Evaluator
    from workers.video import EpisodeRecorder

    envelopes: list[ActionEnvelope] = []
    video = None
    # The replay's page is recycled for the evaluation, as a worker's agent pages are: one editor to open.
    async with BrowserSession() as session, EditorPool(session, spare=0) as pool:
        async with pool.editor() as editor:
            editor.uses += 1  # an episode's use: the pool recycles the page (or closes it) when it comes back
            await editor.load_project(project)
            recorder = EpisodeRecorder(editor.page, record) if record is not None and record.video else None
            if recorder is not None:
                await recorder.start()
            try:
                await _perform(editor, actions, envelopes, console)
            finally:
                if recorder is not None:
                    video = await (await recorder.stop())
            if show_final:
                console.print((await composite.observe(editor)).text, markup=False, highlight=False)
            final = await editor.save_project()
        result = await Evaluator(session, pool).evaluate(final, task_spec)  # type: ignore[arg-type]
    return envelopes, final, result, video


async def _perform(
    editor: Editor, actions: list[CompositeAction], envelopes: list[ActionEnvelope], console: Console
) -> None:
    """Each action in turn, its envelope printed as it comes."""
    from workers import composite

    for number, action in enumerate(actions, start=1):
        envelope = await composite.execute(editor, action.api, action.args)
        envelopes.append(envelope)
        outcome = (
            f"[green]ok[/green] {escape(json.dumps(envelope.data))}"
            if envelope.success
            else f"[red]{envelope.error.code if envelope.error else '?'}[/red] "
            f"{escape(envelope.error.message if envelope.error else '')}"
        )
        console.print(f"{number:>3} {escape(action.api)} {escape(json.dumps(action.args))} -> {outcome}")


@click.command("replay", epilog="Example: scratchworld replay tasks sum_two_numbers --save final.sb3 --observe")
@click.argument("suite_dir", type=click.Path(file_okay=False, path_type=Path))
@click.argument("task_id")
@click.argument("trajectory", required=False, type=click.Path(exists=True, dir_okay=False, path_type=Path))
@click.option("--save", type=click.Path(dir_okay=False, path_type=Path), help="Write the resulting project (.sb3).")
@click.option(
    "--json", "json_file", type=click.Path(dir_okay=False, path_type=Path), help="Write envelopes and verdict."
)
@click.option("--observe", "show_final", is_flag=True, help="Print the final observation.")
@click.option(
    "--video",
    type=click.Path(dir_okay=False, path_type=Path),
    help="Record the editor while the trajectory is replayed, as an H.264 MP4 written here.",
)
@click.option(
    "--fps", type=click.IntRange(1, 30), default=5, show_default=True, help="Video frames per second at most."
)
@evaluation_seed_option
def replay_command(
    suite_dir: Path,
    task_id: str,
    trajectory: Path | None,
    save: Path | None,
    json_file: Path | None,
    show_final: bool,
    video: Path | None,
    fps: int,
    seed: int,
) -> None:
    """Replay TRAJECTORY (default: the task's golden one) on TASK_ID's initial project and evaluate it.

    Exit status: 0 all tests passed, 1 some failed, 3 no verdict.
    """
    task = load_suite(suite_dir).task(task_id)
    if trajectory is not None:
        actions = read_trajectory(trajectory)
    else:
        actions = task.trajectory() or []
        if task.golden_trajectory is None:
            raise click.UsageError(f"task {task_id} has no golden trajectory; give a TRAJECTORY file")
    from scratchworld_dist.sweep import read_project

    console = make_console()
    initial = read_project(task.initial_project, ProjectLimits())
    record = RecordSettings(video=True, fps=fps) if video is not None else None
    envelopes, final, result, recorded = asyncio.run(
        _replay(initial, actions, task.evaluation_spec(seed=seed), console, show_final, record)
    )
    render_result(result, console)
    if video is not None:
        if recorded is None:
            console.print(f"[yellow]no video: the page sent no frame[/yellow] ({escape(str(video))} not written)")
        else:
            video.write_bytes(recorded.mp4)
            info = recorded.info
            size = f"{len(recorded.mp4):,} bytes, {info.duration_s:.1f} s, {info.frames} frames"
            console.print(f"video: {escape(str(video))} ({size})")
    if save is not None:
        save.write_bytes(final)
    if json_file is not None:
        report = {
            "task_id": task_id,
            "steps": [e.model_dump(mode="json") for e in envelopes],
            "eval": {"success": result.success, "passed": result.passed, "total": result.total, "psr": result.psr},
        }
        json_file.write_text(json.dumps(report, indent=2) + "\n", encoding="utf-8")
    if result.error is not None:
        raise click.exceptions.Exit(EXIT_NO_VERDICT)
    if not result.success:
        raise click.exceptions.Exit(EXIT_NOT_PASSED)


async def _observe_all(project: bytes) -> list[str]:
    from workers import composite
    from workers.editor import BrowserSession

    texts = []
    async with BrowserSession() as session, session.editor() as editor:
        await editor.load_project(project)
        for target in (await composite.observe(editor)).targets:
            api, args = ("select_stage", {}) if target.is_stage else ("select_sprite", {"name": target.name})
            await composite.execute(editor, api, args)
            texts.append((await composite.observe(editor)).text)
    return texts


@click.command("observe", epilog="Example: scratchworld observe tasks/sum_two_numbers/initial.sb3")
@click.argument("project", type=click.Path(exists=True, dir_okay=False, path_type=Path))
def observe_command(project: Path) -> None:
    """Print the composite observation of every target of PROJECT (.sb3)."""
    data = read_project_file(project)
    try:
        check_project(data)  # before a browser starts; the message names the file
    except ProjectFormatError as exc:
        raise ProjectFormatError(f"{project}: {exc}") from exc
    for text in asyncio.run(_observe_all(data)):
        click.echo(text + "\n" + "=" * 60)
