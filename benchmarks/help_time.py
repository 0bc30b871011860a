"""Prints the wall time (and CPU time) of ``scratchworld --help`` and of each command's ``--help``.

    .venv/bin/python benchmarks/help_time.py [--runs 5] [--commands run,plan,...]

Each figure is the median of ``--runs`` fresh processes of the installed entry point (``.venv/bin/scratchworld``,
as a user types it), so every run pays Python's start and every import the command's help needs; the target is
under 1 s on an idle machine. CPU is the process's user + system time (from ``os.wait4``): on a loaded machine
the wall time grows with the load and the CPU time barely does, so both are printed, with the load average.
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import time
from pathlib import Path

ENTRY_POINT = Path(sys.executable).with_name("scratchworld")


def one_run(args: list[str]) -> tuple[float, float]:
    """Wall and CPU seconds of one ``scratchworld ARGS --help``, which must succeed."""
    started = time.perf_counter()
    process = subprocess.Popen([str(ENTRY_POINT), *args, "--help"], stdout=subprocess.DEVNULL)
    _, status, usage = os.wait4(process.pid, 0)
    wall = time.perf_counter() - started
    process.returncode = os.waitstatus_to_exitcode(status)
    if process.returncode != 0:
        raise SystemExit(f"scratchworld {' '.join(args)} --help exited {process.returncode}")
    return wall, usage.ru_utime + usage.ru_stime


def command_paths() -> list[list[str]]:
    """Every command's path (``drag make``), read from the CLI itself."""
    import click

    from scratchworld_dist.cli._main import cli

    context = click.Context(cli)
    paths: list[list[str]] = []

    def walk(prefix: list[str], group: click.Group) -> None:
        for name in group.list_commands(context):
            command = group.get_command(context, name)
            paths.append([*prefix, name])
            if isinstance(command, click.Group):
                walk([*prefix, name], command)

    walk([], cli)
    return paths


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--runs", type=int, default=5, help="Runs per command (the median is printed).")
    parser.add_argument("--commands", help="Comma-separated commands (default: all of them).")
    options = parser.parse_args()
    paths = [[]] + ([name.split() for name in options.commands.split(",")] if options.commands else command_paths())
    print(f"load average {os.getloadavg()[0]:.2f} on {os.cpu_count()} CPUs; median of {options.runs} runs")
    print(f"{'command':<34} {'wall s':>7} {'cpu s':>7}")
    walls = []
    for path in paths:
        runs = [one_run(path) for _ in range(options.runs)]
        wall, cpu = statistics.median(r[0] for r in runs), statistics.median(r[1] for r in runs)
        walls.append(wall)
        print(f"{' '.join(['scratchworld', *path]):<34} {wall:>7.2f} {cpu:>7.2f}")
    print(f"slowest {max(walls):.2f} s wall; load average now {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()
