"""Changes to a sweep config given on the command line (``--model``, ``--tasks``, ``--set key=value``...).

They are applied to the file's data before it is validated, so a bad override is reported exactly as the
same mistake in the file would be (``tasks.limit: Input should be greater than 0``), and the run's manifest
records the config as overridden. A key that moved into a kind's section keeps its old spelling here
(``--modes``, ``--set max_steps=9`` set ``episodes.modes`` and ``episodes.max_steps``).
"""

from __future__ import annotations

from typing import Any

import yaml
from pydantic import BaseModel, Field

from scratchworld_dist._errors import ConfigError
from scratchworld_dist.sweep._former_keys import Notice, moved_keys, moved_notice


class SweepOverrides(BaseModel):
    """What the command line changes in a sweep config (empty fields change nothing)."""

    models: list[str] = Field(default_factory=list)
    """Models to run: a config model's name or LiteLLM string selects it, anything else is a LiteLLM model."""

    tasks: list[str] = Field(default_factory=list)
    """Task (or item) ids to run: ``tasks.ids``."""

    limit: int | None = None
    """Run only the first N selected items: ``tasks.limit``."""

    seeds: str | None = None
    """A seed count (``3``) or the seeds themselves (``0,4,7``)."""

    modes: list[str] = Field(default_factory=list)
    """Modes to run: ``episodes.modes``."""

    settings: list[str] = Field(default_factory=list)
    """``dotted.key=value`` assignments, each value read as YAML (``limits.retries=2``, ``drag.types=[T1]``)."""

    values: dict[str, Any] = Field(default_factory=dict)
    """Dotted keys and their values as they are (the Python API's keyword arguments), applied last."""

    def apply(self, data: dict[str, Any], notice: Notice | None = None) -> dict[str, Any]:
        """``data`` (a config file's mapping) with these changes, the ``--set`` ones last; ``notice`` hears of
        each key given in a former spelling (``max_steps`` for ``episodes.max_steps``)."""
        changed, moved = dict(data), moved_keys()
        if self.models:
            changed["models"] = _chosen_models(data.get("models"), self.models)
        if self.tasks:
            _assign(changed, ["tasks", "ids"], _split(self.tasks))
        if self.limit is not None:
            _assign(changed, ["tasks", "limit"], self.limit)
        if self.seeds is not None:
            _assign(changed, ["seeds"], _seeds(self.seeds))
        if self.modes:
            _assign(changed, _current(["modes"], moved), _split(self.modes))
        for setting in self.settings:
            key, sep, value = setting.partition("=")
            path = key.strip().split(".")
            if not sep or not all(path):
                raise ConfigError(f"--set {setting!r}: write it as dotted.key=value")
            try:
                parsed = yaml.safe_load(value)
            except yaml.YAMLError:
                raise ConfigError(f"--set {key}: the value is not valid YAML") from None
            _assign(changed, _current(path, moved, notice), parsed)
        for key, value in self.values.items():
            _assign(changed, _current(key.split("."), moved, notice), value)
        return changed


def _current(path: list[str], moved: dict[str, str], notice: Notice | None = None) -> list[str]:
    """``path`` as the config spells it now: a key that moved into a section, under its section."""
    section = moved.get(path[0])
    if section is None:
        return path
    if notice is not None:
        notice(moved_notice(path[0], section))
    return [section, *path]


def _split(values: list[str]) -> list[str]:
    """Repeated flags and comma-separated lists alike: ``--tasks a,b --tasks c`` is a, b, c."""
    return [part.strip() for value in values for part in value.split(",") if part.strip()]


def _seeds(value: str) -> int | list[int]:
    parts = _split([value])
    try:
        numbers = [int(part) for part in parts]
    except ValueError:
        raise ConfigError(f"--seeds {value!r}: give a count (3) or the seeds (0,4,7)") from None
    return numbers[0] if len(numbers) == 1 and "," not in value else numbers


def _chosen_models(entries: Any, wanted: list[str]) -> list[Any]:
    """The config's model entries ``wanted`` names (by name or LiteLLM string), others as new entries."""
    known = [entry for entry in entries or [] if isinstance(entry, dict)]
    chosen: list[Any] = []
    for name in _split(wanted):
        match = [entry for entry in known if name in (entry.get("name"), entry.get("model"))]
        chosen += match or [{"model": name}]
    return chosen


def _assign(data: dict[str, Any], path: list[str], value: Any) -> None:
    """Set ``data[path[0]][path[1]]... = value``, making the mappings on the way (a scalar there is an error)."""
    node = data
    for depth, key in enumerate(path[:-1]):
        child = node.get(key)
        if child is None:
            child = {}
        elif not isinstance(child, dict):
            where = ".".join(path[: depth + 1])
            raise ConfigError(f"--set {'.'.join(path)}: {where} is not a section of the config")
        node[key] = child = dict(child)
        node = child
    node[path[-1]] = value
