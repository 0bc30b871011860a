"""Entry point: the command group (the commands every benchmark shares, then each kind's own) and the one place
user errors become one-line messages."""

from __future__ import annotations

import logging
import sys

import click

from scratchworld_dist._errors import ScratchWorldError
from scratchworld_dist.cli._editor import capacity_command, gui_command
from scratchworld_dist.cli._kind import KindCommands
from scratchworld_dist.cli._report import report_command, schemas_command
from scratchworld_dist.cli._run import plan_command, run_command
from scratchworld_dist.cli._status import status_command
from scratchworld_dist.cli._view import view_command
from scratchworld_dist.kinds import job_kinds

EXIT_USER_ERROR = 2
EXIT_INTERRUPTED = 130


LOG_LEVELS = ("debug", "info", "warning", "error")


class _Commands(click.Group):
    """The shared commands, and each installed kind's own (a plugin's too), added when a command is first looked
    up: loading the kinds imports their code, which must not happen while this package is being imported."""

    _kinds_added = False

    def _add_kind_commands(self) -> None:
        if not self._kinds_added:
            self._kinds_added = True
            for kind in job_kinds(KindCommands):
                for command in kind.commands():
                    self.add_command(command)

    def list_commands(self, ctx: click.Context) -> list[str]:
        self._add_kind_commands()
        return super().list_commands(ctx)

    def get_command(self, ctx: click.Context, cmd_name: str) -> click.Command | None:
        self._add_kind_commands()
        return super().get_command(ctx, cmd_name)


@click.group(cls=_Commands, context_settings={"help_option_names": ["-h", "--help"]})
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
