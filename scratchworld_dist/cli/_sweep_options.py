"""The options ``run`` and ``plan`` share to change a sweep config without editing it."""

from __future__ import annotations

import functools
from collections.abc import Callable
from typing import Any

import click

from scratchworld_dist.sweep import SweepOverrides

_OPTIONS = (
    click.option(
        "--model", "models", multiple=True, help="Run this model (a config model's name, or a LiteLLM model)."
    ),
    click.option("--tasks", multiple=True, help="Run these task or item ids (comma-separated or repeated)."),
    click.option("--limit", type=click.IntRange(min=1), help="Run only the first N selected tasks or items."),
    click.option("--seeds", help="A seed count (3) or the seeds themselves (0,4,7)."),
    click.option("--modes", multiple=True, help="Run these modes (composite, primitive)."),
    click.option(
        "--set", "settings", multiple=True, metavar="KEY=VALUE", help="Set any config field (limits.retries=2)."
    ),
)


def sweep_overrides(command: Callable[..., Any]) -> Callable[..., Any]:
    """Add the options; the command receives them as one ``overrides: SweepOverrides``."""

    @functools.wraps(command)
    def wrapped(**kwargs: Any) -> Any:
        fields = {name: kwargs.pop(name) for name in ("models", "tasks", "limit", "seeds", "modes", "settings")}
        return command(
            overrides=SweepOverrides(**{k: list(v) if isinstance(v, tuple) else v for k, v in fields.items()}), **kwargs
        )

    for option in reversed(_OPTIONS):
        wrapped = option(wrapped)
    return wrapped
