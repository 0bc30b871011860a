"""Where a rendered report goes: stdout, or the ``--out`` file with a line on stderr saying so."""

from __future__ import annotations

import sys
from pathlib import Path

import click


def emit(text: str, out: Path | None, warnings: list[str], what: str) -> None:
    """Warnings to stderr, then ``text`` to stdout or ``out`` (an unwritable file is a one-line user error).

    ``text`` holds the warnings too: when it is shown on this terminal they are not said twice.
    """
    if out is not None or not sys.stdout.isatty():
        for warning in warnings:
            click.echo(f"warning: {warning}", err=True)
    if out is None:
        click.echo(text, nl=False)
        return
    try:
        out.write_text(text, encoding="utf-8")
    except OSError as exc:
        raise click.FileError(str(out), hint=str(exc)) from exc
    click.echo(f"wrote {what} to {out}", err=True)
