"""docs/commands.md against the CLI, both ways: every command is listed, every listed command exists, and every
option a line shows is one its command takes; so the page cannot drift from the code."""

from __future__ import annotations

import re

import click

from tests.conftest import REPO
from tests.scratchworld_dist.cli.test_grammar import every_command

DOC = REPO / "docs" / "commands.md"


def documented() -> dict[str, list[str]]:
    """Each command line of the page's first bash block: the command's path and the options it shows."""
    text = DOC.read_text()
    block = text.split("```bash", 1)[1].split("```", 1)[0]
    commands = dict(every_command())
    lines: dict[str, list[str]] = {}
    for line in block.strip().splitlines():
        words = line.split("#", 1)[0].split()
        assert words[0] == "scratchworld", line
        path = words[1]
        if isinstance(commands.get(path), click.Group):
            path = f"{path} {words[2]}"
        assert path not in lines, f"{path} is listed twice"
        lines[path] = re.findall(r"--[a-z][a-z-]*", line.split("#", 1)[0])
    return lines


def test_every_command_is_listed_and_every_listed_command_exists() -> None:
    leaves = {path for path, command in every_command() if not isinstance(command, click.Group)}
    assert set(documented()) == leaves


def test_every_option_the_page_shows_is_one_its_command_takes() -> None:
    commands = dict(every_command())
    for path, options in documented().items():
        taken = {name for param in commands[path].params for name in getattr(param, "opts", [])}
        taken |= {name for param in commands[path].params for name in getattr(param, "secondary_opts", [])}
        assert set(options) <= taken, (path, sorted(set(options) - taken))
