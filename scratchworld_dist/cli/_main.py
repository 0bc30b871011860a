"""Entry point: the command group (the commands every benchmark shares, then each kind's own) and the one place
user errors become one-line messages.

Commands are imported when they are looked up, not when the group is built: ``scratchworld --help`` reads only
the command modules (click and light imports at their top), and ``scratchworld run`` loads what a sweep needs.
Kinds declare their commands as entry points of ``scratchworld.commands`` (pyproject.toml registers the
built-in ones; a plugin's package its own), so listing them imports no kind.
"""

from __future__ import annotations

import importlib
import logging
import sys

import click

from scratchworld_dist._errors import ScratchWorldError
from workers import Registry

EXIT_USER_ERROR = 2
EXIT_INTERRUPTED = 130

LOG_LEVELS = ("debug", "info", "warning", "error")

COMMAND_ENTRY_POINTS = "scratchworld.commands"
"""Entry-point group of the commands a kind adds (``validate = "package.module:validate_command"``)."""

SHARED_COMMANDS = {
    "run": "scratchworld_dist.cli._run:run_command",
    "plan": "scratchworld_dist.cli._run:plan_command",
    "status": "scratchworld_dist.cli._status:status_command",
    "report": "scratchworld_dist.cli._report:report_command",
    "schemas": "scratchworld_dist.cli._report:schemas_command",
    "view": "scratchworld_dist.cli._view:view_command",
    "list": "scratchworld_dist.cli._list:list_group",
    "gui": "scratchworld_dist.cli._editor:gui_command",
    "capacity": "scratchworld_dist.cli._editor:capacity_command",
}
"""The commands every benchmark shares, by name: ``module:attribute``."""


class CommandPluginError(ScratchWorldError):
    """A command's entry point cannot be imported or does not name a click command."""


def _not_a_command(name: str, found: object) -> str | None:
    if not isinstance(found, click.Command):
        return "is not a click command"
    return None if found.name == name else f"names a command called {found.name!r}"


_KIND_COMMANDS: Registry[click.Command] = Registry(COMMAND_ENTRY_POINTS, "command", CommandPluginError, _not_a_command)


def _set_log_level(ctx: click.Context, param: click.Parameter, value: str | None) -> None:
    if value is None:
        return
    logging.basicConfig(level=value.upper(), format="%(levelname)s %(name)s: %(message)s")
    if param.default is None:  # given after the command: it wins over the group's default, set before it
        logging.getLogger().setLevel(value.upper())


def _log_level_option(default: str | None) -> click.Option:
    return click.Option(
        ["--log-level"],
        type=click.Choice(LOG_LEVELS),
        default=default,
        show_default=default is not None,
        expose_value=False,
        is_eager=True,
        callback=_set_log_level,
        help="What this process logs to stderr (the editor, model calls, rate limits); workers log to Ray's logs "
        "folder. Accepted before or after the command.",
    )


def with_global_options(command: click.Command) -> click.Command:
    """``command`` (and a group's subcommands) taking the group's options too, so ``scratchworld run CONFIG
    --log-level info`` means what ``scratchworld --log-level info run CONFIG`` does."""
    if not any(param.name == "log_level" for param in command.params):
        command.params.append(_log_level_option(None))
    if isinstance(command, click.Group):
        for sub in command.commands.values():
            with_global_options(sub)
    return command


def _load(target: str) -> click.Command:
    module, _, attribute = target.partition(":")
    command: click.Command = getattr(importlib.import_module(module), attribute)
    return command


class _Commands(click.Group):
    """The shared commands and each installed kind's own (a plugin's too), each imported when first looked up."""

    def list_commands(self, ctx: click.Context) -> list[str]:
        return sorted({*self.commands, *SHARED_COMMANDS, *_KIND_COMMANDS.names()})

    def get_command(self, ctx: click.Context, cmd_name: str) -> click.Command | None:
        if cmd_name not in self.commands:
            if cmd_name in SHARED_COMMANDS:
                command = _load(SHARED_COMMANDS[cmd_name])
            else:
                point = _KIND_COMMANDS.points().get(cmd_name)
                if point is None:
                    return None
                command = _KIND_COMMANDS.load(point)
            self.add_command(with_global_options(command), cmd_name)
        return self.commands[cmd_name]


@click.group(
    cls=_Commands,
    context_settings={"help_option_names": ["-h", "--help"]},
    epilog="Example: scratchworld run configs/demo.yaml --tasks a,b --log-level info. Shell completion: see "
    'docs/commands.md (eval "$(_SCRATCHWORLD_COMPLETE=bash_source scratchworld)").',
)
@click.version_option(package_name="scratchworld-dist", prog_name="scratchworld", message="%(prog)s %(version)s")
def cli() -> None:
    """Evaluate GUI agents on ScratchWorld tasks in the Scratch 3 editor."""


cli.params.append(_log_level_option("warning"))


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
