"""One grammar across commands: ``--address`` (and ``RAY_ADDRESS``) wherever a cluster is joined, ``--tasks``
repeatable and comma-separated wherever tasks are chosen, the group's options after the command too, one message
for a folder that is not a run, "did you mean" for a config key, an example in every command's help."""

from __future__ import annotations

import logging
from pathlib import Path

import click
import pytest

from scratchworld_dist.cli._main import cli
from scratchworld_dist.cli._options import REPORT_FORMATS, tasks_option
from tests.conftest import REPO
from tests.support.cli_runner import invoke
from tests.support.closed_port import closed_port
from tests.support.run_dirs import job, make_run


def every_command() -> list[tuple[str, click.Command]]:
    """Each command by its path (``drag validate``), groups and their subcommands alike."""
    context = click.Context(cli)
    found: list[tuple[str, click.Command]] = []

    def walk(prefix: str, group: click.Group) -> None:
        for name in group.list_commands(context):
            command = group.get_command(context, name)
            assert command is not None, name
            found.append((f"{prefix}{name}", command))
            if isinstance(command, click.Group):
                walk(f"{prefix}{name} ", command)

    walk("", cli)
    return found


def test_every_command_s_help_shows_an_example() -> None:
    for path, _ in every_command():
        done = invoke(*path.split(), "--help")
        assert done.returncode == 0, (path, done.stderr)
        assert "Example: scratchworld " + path.split()[0] in done.stdout, path


def test_regrade_joins_the_cluster_address_or_ray_address_names(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    run = make_run(tmp_path / "run", [job("j1", artifact_dir="artifacts/j1")], planned=1, tasks=1)
    (run / "artifacts" / "j1").mkdir(parents=True)
    (run / "artifacts" / "j1" / "final.sb3").write_bytes(b"PK\x03\x04 not opened: Ray is reached first")
    out = str(tmp_path / "out")
    monkeypatch.delenv("RAY_ADDRESS", raising=False)
    with closed_port() as port:
        for spelling in ("--address", "--ray-address"):  # the former spelling still works
            done = invoke("regrade", str(run), "--out", out, spelling, f"127.0.0.1:{port}")
            assert done.returncode == 2, done.stderr
            assert f"cannot reach the Ray cluster at 127.0.0.1:{port}" in done.stderr
        monkeypatch.setenv("RAY_ADDRESS", f"127.0.0.1:{port}")
        done = invoke("regrade", str(run), "--out", out)
        assert done.returncode == 2 and f"cannot reach the Ray cluster at 127.0.0.1:{port}" in done.stderr
    help_text = invoke("regrade", "--help").stdout
    assert "--address" in help_text and "--ray-address" not in help_text  # kept, but not shown


def test_every_command_that_joins_a_cluster_spells_it_address() -> None:
    joining = [path for path, command in every_command() if any("--ray-address" in p.opts for p in command.params)]
    assert sorted(joining) == ["audit", "regrade", "run"]
    for path, command in every_command():
        names = [name for param in command.params for name in getattr(param, "opts", [])]
        assert not [name for name in names if "address" in name and name not in ("--address", "--ray-address")], path


@click.command()
@tasks_option
def _echo_tasks(task_ids: list[str] | None) -> None:
    click.echo(repr(task_ids))


def test_tasks_are_repeatable_and_comma_separated_alike() -> None:
    runner = click.testing.CliRunner()
    assert runner.invoke(_echo_tasks, ["--tasks", "a,b", "--tasks", "c", "--tasks", " d , "]).output == (
        "['a', 'b', 'c', 'd']\n"
    )
    assert runner.invoke(_echo_tasks, []).output == "None\n"
    for path in ("validate", "flakes", "oracle-plan", "drag validate", "audit", "run", "plan"):
        command = dict(every_command())[path]
        tasks = next(param for param in command.params if "--tasks" in getattr(param, "opts", []))
        assert tasks.multiple, path  # a repeated flag accumulates instead of keeping the last


def test_validate_keeps_the_tasks_of_every_repeated_flag() -> None:
    # Keeping only the last flag would validate sum_two_numbers; all of them, the first one is refused.
    done = invoke("validate", str(REPO / "tasks"), "--tasks", "no_such_a", "--tasks", "sum_two_numbers")
    assert done.returncode == 2
    assert "no task 'no_such_a'" in done.stderr, done.stderr


def test_the_log_level_is_taken_after_the_command_too(tmp_path: Path) -> None:
    root = logging.getLogger()
    before = root.level
    try:
        done = invoke("status", str(tmp_path), "--log-level", "debug")
        assert "no such option" not in done.stderr
        assert root.level == logging.DEBUG
        done = invoke("--log-level", "info", "list", "benchmarks", "--log-level", "error")
        assert done.returncode == 0, done.stderr
        assert root.level == logging.ERROR  # after the command wins
    finally:
        root.setLevel(before)


def test_a_folder_that_is_no_run_gets_one_message_from_every_command(tmp_path: Path) -> None:
    empty = tmp_path / "empty"
    empty.mkdir()
    commands = [
        ("status", str(empty)),
        ("report", str(empty)),
        ("export", str(empty), "--format", "leaderboard", "--out", str(tmp_path / "x")),
        ("compare", str(empty), str(empty)),
        ("regrade", str(empty), "--out", str(tmp_path / "y")),
        ("view", str(empty), "--export", str(tmp_path / "z")),
    ]
    for args in commands:
        done = invoke(*args)
        assert done.returncode == 2, (args, done.stderr)
        assert done.stderr == f"error: {empty}: not a scratchworld run directory (no manifest.json in it)\n", args
    missing = tmp_path / "missing"
    for args in (("status", str(missing)), ("report", str(missing))):
        assert invoke(*args).stderr == f"error: {missing}: not a scratchworld run directory (no such folder)\n"


def test_an_unknown_config_key_gets_the_closest_known_one(tmp_path: Path) -> None:
    config = tmp_path / "typo.yaml"
    config.write_text(
        f"name: t\nsuite: {REPO / 'tasks'}\nmodls: []\nlimits: {{retires: 2}}\nepisodes: {{max_step: 3}}\n"
        "agent: {name: oracle, parms: {}}\nzzzz: 1\n"
    )
    done = invoke("plan", str(config))
    assert done.returncode == 2
    assert "modls: unknown key; did you mean 'models'?" in done.stderr
    assert "limits.retires: unknown key; did you mean 'retries'?" in done.stderr
    assert "episodes.max_step: unknown key; did you mean 'max_steps'?" in done.stderr
    assert "agent.parms: unknown key; did you mean 'params'?" in done.stderr
    assert "zzzz: unknown key;" not in done.stderr and "zzzz: unknown key" in done.stderr


def test_the_cli_s_format_choices_are_the_library_s() -> None:
    from scratchworld_dist.kinds.tasks.cli._export import FORMATS as CLI_EXPORT_FORMATS
    from scratchworld_dist.kinds.tasks.exports import EXPORT_FORMATS
    from scratchworld_dist.reports import FORMATS

    assert REPORT_FORMATS == FORMATS
    assert CLI_EXPORT_FORMATS == EXPORT_FORMATS
