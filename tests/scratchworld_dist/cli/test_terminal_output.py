"""What the commands print, as a user sees it: `--version`; `compare`'s warning said once on a terminal and its
per-task rows counted as what they are; `status` piped to a file or a pager as whole, plain lines.

The terminal cases run `scratchworld` as a real process on a pseudo-terminal, the piped ones on pipes.
"""

from __future__ import annotations

import os
import pty
import subprocess
from importlib.metadata import version
from pathlib import Path

from tests.support.cli_runner import invoke
from tests.support.run_dirs import job, make_run
from tests.support.sweep_driver import SCRATCHWORLD

ANSI_ESCAPE = "\x1b["


def on_terminal(*args: str) -> str:
    """What ``scratchworld ARGS`` shows on a terminal (stdout and stderr both on one pseudo-terminal)."""
    leader, follower = pty.openpty()
    process = subprocess.Popen([SCRATCHWORLD, *args], stdin=subprocess.DEVNULL, stdout=follower, stderr=follower)
    os.close(follower)
    shown = bytearray()
    while True:
        try:
            chunk = os.read(leader, 65536)
        except OSError:  # EIO: the process closed its end
            break
        if not chunk:
            break
        shown += chunk
    os.close(leader)
    assert process.wait(timeout=120) == 0, shown.decode(errors="replace")
    return shown.decode().replace("\r\n", "\n")


def piped(*args: str) -> subprocess.CompletedProcess[str]:
    done = subprocess.run([SCRATCHWORLD, *args], capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    return done


def two_runs(root: Path) -> tuple[Path, Path]:
    """Two runs of one system on 12 tasks in both modes, one seed: 24 paired jobs."""
    runs = []
    for name, shift in (("a", 0), ("b", 1)):
        rows = [
            job(f"{name}-{task}-{mode}", "passed" if (task + shift + index) % 3 else "failed", mode=mode,
                task_id=f"task{task:02d}", task_hash=f"h{task}")
            for task in range(12) for index, mode in enumerate(("composite", "primitive"))
        ]  # fmt: skip
        runs.append(make_run(root / name, rows, planned=24, tasks=12))
    return runs[0], runs[1]


WARNING = "tasks have several paired jobs (seeds, modes, settings)"


def test_version_prints_the_installed_package_version() -> None:
    done = invoke("--version")
    assert (done.returncode, done.stdout, done.stderr) == (0, f"scratchworld {version('scratchworld-dist')}\n", "")


def test_compare_says_its_warning_once_on_a_terminal_and_in_both_streams_when_piped(tmp_path: Path) -> None:
    a, b = two_runs(tmp_path)
    shown = on_terminal("compare", str(a), str(b))
    assert shown.count(WARNING) == 1
    assert f"Warning: {WARNING}" in shown  # in the comparison itself
    done = piped("compare", str(a), str(b))
    assert done.stderr.count(WARNING) == 1 and done.stdout.count(WARNING) == 1  # a file keeps it; so does the user


def test_compare_counts_task_and_mode_rows_as_such(tmp_path: Path) -> None:
    a, b = two_runs(tmp_path)
    by_mode = invoke("compare", str(a), str(b))
    assert by_mode.returncode == 0
    assert "24 jobs over 12 tasks" in by_mode.stdout
    assert "## Per task and mode (24 rows over 12 task(s) and 2 mode(s)): A wins " in by_mode.stdout
    assert "24 task" not in by_mode.stdout
    one_mode = invoke("compare", f"{a}@composite", f"{b}@composite")
    assert one_mode.returncode == 0
    assert "## Per task (12 task(s)): A wins " in one_mode.stdout


def test_status_piped_prints_whole_plain_lines(tmp_path: Path) -> None:
    deep = tmp_path / ("a-run-directory-with-a-long-name-" * 3) / "run"
    run = make_run(deep, [job("j1", task_id="t1"), job("j2", "failed", task_id="t2")], planned=5, tasks=3)
    done = piped("status", str(run))
    lines = done.stdout.splitlines()
    assert lines[0] == f"sweep  {run}"  # longer than 80 columns, on one line
    assert lines[1].startswith("suite ours (3 tasks, hash suite1); harness ")
    assert lines[2] == "2/5 decided: passed 1, failed 1; error 0; not yet run 3; attempts recorded 2"
    assert ANSI_ESCAPE not in done.stdout and "[bold]" not in done.stdout
    shown = on_terminal("status", str(run))
    assert ANSI_ESCAPE in shown  # a terminal still gets the styled heading
