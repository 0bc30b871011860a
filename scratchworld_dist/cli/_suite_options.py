"""How the commands that check a suite choose its tasks and editors: the same options, read the same way."""

from __future__ import annotations

from collections.abc import Callable
from typing import TypeVar

import click

_Command = TypeVar("_Command", bound=Callable[..., object])


def comma_list(text: str | None) -> list[str] | None:
    """The items of a comma-separated option, blanks dropped; None when the option was not given."""
    return [item.strip() for item in text.split(",") if item.strip()] if text else None


tasks_option = click.option("--tasks", "task_ids", help="Comma-separated task ids (default: all).")


def suite_check_options(command: _Command) -> _Command:
    """``--tasks``, ``--task-list``, ``--parallel`` and ``--profile``, as ``validate`` and ``flakes`` take them."""
    for option in reversed(
        (
            tasks_option,
            click.option("--task-list", help="Upstream task list, e.g. all_tasks or 15_tasks."),
            click.option(
                "--parallel", type=click.IntRange(min=1), default=1, show_default=True, help="Editors at a time."
            ),
            click.option(
                "--profile",
                type=click.Choice(["native", "upstream"]),
                help="Evaluation profile (default: upstream for upstream clones, native for our suites).",
            ),
        )
    ):
        command = option(command)
    return command
