"""The task-episode kind's own commands: checking a suite (``validate``, ``flakes``, ``evaluate``, ``replay``,
``observe``, ``oracle-plan``) and working on episode runs (``regrade``, ``compare``, ``export``)."""

import click

from scratchworld_dist.kinds.tasks.cli._compare import compare_command
from scratchworld_dist.kinds.tasks.cli._evaluate import evaluate_command
from scratchworld_dist.kinds.tasks.cli._export import export_command
from scratchworld_dist.kinds.tasks.cli._flakes import flakes_command
from scratchworld_dist.kinds.tasks.cli._oracle_plan import oracle_plan_command
from scratchworld_dist.kinds.tasks.cli._regrade import regrade_command
from scratchworld_dist.kinds.tasks.cli._replay import observe_command, replay_command
from scratchworld_dist.kinds.tasks.cli._validate import validate_command

COMMANDS: list[click.Command] = [
    validate_command,
    flakes_command,
    evaluate_command,
    replay_command,
    observe_command,
    oracle_plan_command,
    regrade_command,
    compare_command,
    export_command,
]

__all__ = ["COMMANDS"]
