"""The options several commands share, declared once and read the same way everywhere: the evaluation
conditions (``--timing``, ``--render``, ``--evaluation-page``), how a suite check chooses its tasks and editors
(``--tasks``, ``--task-list``, ``--parallel``, ``--profile``), the Ray cluster (``--address``), and how ``run``
and ``plan`` change a sweep config without editing it.

Only click is imported here: every command's module imports this one, and ``scratchworld --help`` loads them all.
"""

from __future__ import annotations

import functools
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any, TypeVar

import click

_Command = TypeVar("_Command", bound=Callable[..., object])

timing_option = click.option(
    "--timing",
    type=click.Choice(["ideal", "calibrated"]),
    help="Virtual-clock frame timing: exactly on time, or late by the calibrated per-frame model "
    "(default: calibrated for upstream in virtual time, ideal otherwise).",
)

render_option = click.option(
    "--render",
    type=click.Choice(["on_demand", "every_frame"]),
    help="When evaluations draw the stage: only when a script reads the picture (default), or every frame.",
)

page_option = click.option(
    "--evaluation-page",
    "page",
    type=click.Choice(["bare", "editor"]),
    help="The page evaluations run in: the VM without the editor GUI (default; a script that needs the "
    "editor runs there anyway), or the whole Scratch editor, the reference.",
)


REPORT_FORMATS = ("md", "html", "json")
"""``scratchworld_dist.reports.FORMATS``, spelled here so a command's help does not load the reports (a test checks
the two agree)."""

report_format_option = click.option(
    "--format", "fmt", type=click.Choice(REPORT_FORMATS), default="md", show_default=True, help="Output format."
)

evaluation_seed_option = click.option(
    "--seed",
    type=click.IntRange(min=0),
    default=0,
    show_default=True,
    help="Sweep seed whose random numbers the evaluations draw, as a job of the task at that seed does.",
)


class RunDirParam(click.Path):
    """A run directory to read: a path (checked as ``click.Path`` checks it), or a URL of one on object storage
    (``s3://bucket/run``), opened as a local view whose shards are read in the bucket (``results.remote``)."""

    def __init__(self, *, file_okay: bool = True) -> None:
        super().__init__(file_okay=file_okay, path_type=Path)

    def convert(self, value: Any, param: click.Parameter | None, ctx: click.Context | None) -> Any:
        if isinstance(value, Path) or "://" not in str(value):
            return super().convert(value, param, ctx)
        from scratchworld_dist.results.remote._view import open_view  # fsspec: only for a remote run

        return open_view(str(value))


RUN_DIR = RunDirParam()
RUN_FOLDER = RunDirParam(file_okay=False)


def comma_list(text: str | None) -> list[str] | None:
    """The items of a comma-separated option, blanks dropped; None when the option was not given."""
    return [item.strip() for item in text.split(",") if item.strip()] if text else None


def _id_list(ctx: click.Context, param: click.Parameter, value: Sequence[str]) -> list[str] | None:
    """A repeatable, comma-separated option's items in order, repeated flags accumulating; None when not given."""
    items = [item for text in value for item in comma_list(text) or []]
    return items or None


def id_list_option(*names: str, help: str) -> Callable[[_Command], _Command]:
    """An option of ids that may be repeated and comma-separated alike (``--tasks a,b --tasks c``: a, b, c)."""
    return click.option(*names, multiple=True, callback=_id_list, metavar="ID[,ID...]", help=help)


tasks_option = id_list_option("--tasks", "task_ids", help="Task ids, comma-separated or repeated (default: all).")


class AliasedOption(click.Option):
    """An option whose former spellings still work but are not shown in ``--help`` (``--ray-address``)."""

    def __init__(self, *args: Any, hidden_aliases: Sequence[str] = (), **kwargs: Any) -> None:
        names = list(args[0]) + list(hidden_aliases)
        super().__init__(names, *args[1:], **kwargs)
        self.hidden_aliases = tuple(hidden_aliases)

    def get_help_record(self, ctx: click.Context) -> tuple[str, str] | None:
        shown, self.opts = self.opts, [name for name in self.opts if name not in self.hidden_aliases]
        try:
            return super().get_help_record(ctx)
        finally:
            self.opts = shown


address_option = click.option(
    "--address",
    cls=AliasedOption,
    hidden_aliases=("--ray-address",),
    metavar="HOST:PORT",
    help="Ray cluster to join, or auto (default: RAY_ADDRESS, else a private local Ray).",
)


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


_SWEEP_OPTIONS = (
    click.option(
        "--model", "models", multiple=True, help="Run this model (a config model's name, or a LiteLLM model)."
    ),
    click.option(
        "--tasks", multiple=True, metavar="ID[,ID...]", help="Run these task or item ids (comma-separated or repeated)."
    ),
    click.option(
        "-M",
        "--model-arg",
        "model_args",
        multiple=True,
        metavar="[NAME:]KEY=VALUE",
        help="Set a model setting (temperature=0) or param (top_p=0.9) on every model, or on model NAME only.",
    ),
    click.option("--limit", type=click.IntRange(min=1), help="Run only N of the selected tasks or items."),
    click.option(
        "--sample",
        type=click.Choice(["first", "random"]),
        help="Which N --limit takes: the first in suite order (default) or a random sample.",
    ),
    click.option("--sample-seed", type=click.IntRange(min=0), help="Seed of --sample random (default 0)."),
    click.option(
        "--tag", "tags", multiple=True, metavar="KEY=VALUE", help="Label the run (repeatable; kept in its manifest)."
    ),
    click.option("--seeds", help="A seed count (3) or the seeds themselves (0,4,7)."),
    click.option("--modes", multiple=True, help="Run these modes (composite, primitive)."),
    click.option(
        "--set", "settings", multiple=True, metavar="KEY=VALUE", help="Set any config field (limits.retries=2)."
    ),
)


def sweep_overrides(command: Callable[..., Any]) -> Callable[..., Any]:
    """Add the options ``run`` and ``plan`` share; the command receives them as one ``overrides: SweepOverrides``."""

    @functools.wraps(command)
    def wrapped(**kwargs: Any) -> Any:
        from scratchworld_dist.sweep import SweepOverrides  # the config models: for the command that runs only

        fields = {name: kwargs.pop(name) for name in SweepOverrides.command_line_fields()}
        return command(
            overrides=SweepOverrides(**{k: list(v) if isinstance(v, tuple) else v for k, v in fields.items()}), **kwargs
        )

    for option in reversed(_SWEEP_OPTIONS):
        wrapped = option(wrapped)
    return wrapped
