"""``scratchworld play``: one task, solved by a person, run and judged as any agent's job.

It is a one-job sweep of the ``human`` agent (``agent: {name: human, params: {participant: ...}}``) on the real
episode clock, in a run directory of its own: the editor opens in our Chromium with the task's initial project
and the person works in the page the agent serves on 127.0.0.1; their steps, the verdict and the time are
stored like a model's, so ``view``, ``report`` and ``export`` read them. Running it again resumes: a decided
job is kept, one that ended in an error (a page closed, the time limit) is played again.
``scratchworld gui`` is unrelated: it serves a bare editor with no task, no confinement and no record.
"""

from __future__ import annotations

import getpass
import os
import re
from pathlib import Path

import click

from scratchworld_dist.kinds.tasks.cli._evaluate import EXIT_NO_VERDICT, EXIT_NOT_PASSED

DEFAULT_TIME_LIMIT_S = 1800.0
DEFAULT_MAX_STEPS = 500
"""Steps a person may take (every click, drag, key and typed run is one); a model's sweep usually gives fewer."""

_NAME = re.compile(r"^[A-Za-z0-9][A-Za-z0-9._-]*$")


def _participant(given: str | None) -> str:
    name = given if given is not None else getpass.getuser()
    if not _NAME.match(name) or len(name) > 64:
        raise click.BadParameter(
            f"{name!r}: letters, digits, '.', '_' and '-' only (at most 64)", param_hint="--participant"
        )
    return name


@click.command(
    "play",
    epilog="Example: scratchworld play tasks sum_two_numbers --participant ada --port 8765 "
    "(from a laptop: ssh -L 8765:127.0.0.1:8765 HOST, then open http://127.0.0.1:8765/)",
)
@click.argument("suite_dir", type=click.Path(exists=True, file_okay=False, path_type=Path))
@click.argument("task_id")
@click.option("--mode", type=click.Choice(["primitive", "composite"]), default="primitive", show_default=True)
@click.option("--participant", help="Who plays (default: your user name); part of the job's identity.")
@click.option("--port", type=click.IntRange(1, 65535), default=8765, show_default=True, help="The page's port.")
@click.option(
    "--time-limit", type=click.FloatRange(min=1), default=DEFAULT_TIME_LIMIT_S, show_default=True, help="Seconds."
)
@click.option("--max-steps", type=click.IntRange(min=1), default=DEFAULT_MAX_STEPS, show_default=True)
@click.option(
    "--output",
    type=click.Path(file_okay=False, path_type=Path),
    help="The run directory (default: results/play/PARTICIPANT/TASK_ID-MODE).",
)
def play_command(
    suite_dir: Path,
    task_id: str,
    mode: str,
    participant: str | None,
    port: int,
    time_limit: float,
    max_steps: int,
    output: Path | None,
) -> None:
    """Work on TASK_ID of SUITE_DIR yourself, in a page on 127.0.0.1 that shows the editor live.

    Exit status: 0 all tests passed, 1 some failed, 3 no verdict (an error: play again to resume).
    """
    from scratchworld_dist._run import run_sweep  # imports Ray: only when a job runs
    from scratchworld_dist.suites import load_suite
    from scratchworld_dist.sweep import SweepConfig
    from workers.agents._human import PORT_VARIABLE

    who = _participant(participant)
    load_suite(suite_dir).task(task_id)  # an unknown task stops here, before Ray starts
    config = SweepConfig.model_validate(
        {
            "name": f"play-{who}-{task_id}-{mode}",
            "suite": suite_dir.resolve(),
            "tasks": {"ids": [task_id]},
            "agent": {"name": "human", "params": {"participant": who}},
            "episodes": {"modes": [mode], "max_steps": max_steps, "episode_clock": {"mode": "real"}},
            "limits": {"episode_timeout_s": time_limit, "retries": 0},
            "output": (output or Path("results") / "play" / who / f"{task_id}-{mode}").resolve(),
        }
    )
    os.environ[PORT_VARIABLE] = str(port)  # the worker this process starts reads it
    click.echo(
        f"Open http://127.0.0.1:{port}/ once the editor is up (from another machine: "
        f"ssh -L {port}:127.0.0.1:{port} THIS_HOST). Time limit: {time_limit:g} s."
    )
    summary = run_sweep(config)
    from scratchworld_dist.results import RunStore, effective_rows

    rows = list(effective_rows(RunStore(summary.run_dir).job_rows()))
    outcome = rows[0].outcome if rows else "error"
    if outcome == "error":
        click.echo(f"No verdict (an error); run the same command again to play it again. Results: {summary.run_dir}")
        raise click.exceptions.Exit(EXIT_NO_VERDICT)
    click.echo(f"{outcome.capitalize()}. Results: {summary.run_dir} (scratchworld view {summary.run_dir})")
    if outcome != "passed":
        raise click.exceptions.Exit(EXIT_NOT_PASSED)
