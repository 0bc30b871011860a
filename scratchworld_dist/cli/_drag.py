"""``scratchworld drag``: the single-step drag benchmark's own tools (running it is ``scratchworld run``
with ``benchmark: drag``)."""

from __future__ import annotations

import asyncio
from pathlib import Path

import click


@click.group("drag")
def drag_group() -> None:
    """Single-step drag tasks: generate a suite from projects."""


@drag_group.command("make")
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
    from scratchworld_dist.drag._make import make_drag_suite  # the browser stack, for this command only

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
