"""The one way commands make a rich console: a line is never cut mid-field, and off a terminal it is plain text.

On a terminal rich styles the text and fits tables to the window. Piped or redirected, rich would wrap every
line at 80 columns (its default width there), so a log or ``status > file`` held fields broken over lines:
there each line is printed whole, with no styling, and tables take the width they need.
"""

from __future__ import annotations

import sys

from rich.console import Console

PLAIN_WIDTH = 1_000
"""The width off a terminal: wide enough that no table is squeezed (lines are not wrapped at any width)."""


def make_console(*, stderr: bool = False) -> Console:
    """A console on standard output (or error) as described above."""
    stream = sys.stderr if stderr else sys.stdout
    terminal = stream.isatty()
    return Console(stderr=stderr, soft_wrap=True, width=None if terminal else PLAIN_WIDTH)
