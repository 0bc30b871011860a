"""Entry point: the command group (the commands every benchmark shares, then each kind's own) and the one place
user errors become one-line messages."""

from __future__ import annotations

import logging
import sys

import click

from scratchworld_dist._errors import ScratchWorldError
from scratchworld_dist.cli._capacity import capacity_command
from scratchworld_dist.cli._gui import gui_command
from scratchworld_dist.cli._kind import KindCommands
from scratchworld_dist.cli._plan import plan_command
from scratchworld_dist.cli._report import report_command
from scratchworld_dist.cli._run import run_command
from scratchworld_dist.cli._schemas import schemas_command
from scratchworld_dist.cli._status import status_command
from scratchworld_dist.cli._view import view_command
from scratchworld_dist.kinds import job_kinds

EXIT_USER_ERROR = 2
EXIT_INTERRUPTED = 130


LOG_LEVELS = ("debug", "info", "warning", "error")


@click.group(context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(package_name="scratchworld-dist", prog_name="scratchworld", message="%(prog)s %(version)s")
@click.option(
    "--log-level",
    type=click.Choice(LOG_LEVELS),
    default="warning",
    show_default=True,
    help="What this process logs to stderr (the editor, model calls, rate limits); workers log to Ray's logs folder.",
)
def cli(log_level: str) -> None:
    """Evaluate GUI agents on ScratchWorld tasks in the Scratch 3 editor."""
    logging.basicConfig(level=log_level.upper(), format="%(levelname)s %(name)s: %(message)s")


cli.add_command(gui_command)
cli.add_command(report_command)
cli.add_command(run_command)
cli.add_command(plan_command)
cli.add_command(status_command)
cli.add_command(capacity_command)
cli.add_command(view_command)
cli.add_command(schemas_command)
for _kind in job_kinds(KindCommands):  # each benchmark's own commands (a plugin's too)
    for _command in _kind.commands():
        cli.add_command(_command)


def main() -> None:
    """Run the CLI; our errors print as ``error: ...`` without a traceback."""
    try:
        # Outside standalone mode click returns the exit code of ``Exit`` instead of raising.
        code = cli(standalone_mode=False)
    except click.ClickException as exc:  # a bad argument, option or file: one line and exit 2, like our own errors
        click.echo(f"error: {_click_message(exc)}", err=True)
        sys.exit(EXIT_USER_ERROR)
    except click.exceptions.Abort:
        sys.exit(EXIT_INTERRUPTED)
    except KeyboardInterrupt:
        click.echo("interrupted", err=True)
        sys.exit(EXIT_INTERRUPTED)
    except ScratchWorldError as exc:
        click.echo(f"error: {exc}", err=True)
        sys.exit(EXIT_USER_ERROR)
    except OSError as exc:  # a file or folder the user named cannot be used: say which, no traceback
        click.echo(f"error: {exc}", err=True)
        sys.exit(EXIT_USER_ERROR)
    sys.exit(code if isinstance(code, int) else 0)


def _click_message(exc: click.ClickException) -> str:
    """Click's message on one line, with the command it concerns and where to read its usage."""
    message = " ".join(exc.format_message().split())
    context = getattr(exc, "ctx", None)
    if isinstance(exc, click.UsageError) and context is not None:
        return f"{context.command_path}: {message} (see {context.command_path} --help)"
    return message
