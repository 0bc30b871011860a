"""Changes to a sweep config given on the command line (``--model``, ``-M``, ``--tasks``, ``--set key=value``...).

They are applied to the file's data before it is validated, so a bad override is reported exactly as the
same mistake in the file would be (``tasks.limit: Input should be greater than 0``), and the run's manifest
records the config as overridden. ``--model`` keeps the config's entry of a model it names (its temperature,
max_tokens, endpoint and key variables); a model the config does not name is a new entry with LiteLLM's defaults,
said as a notice, never another entry's settings. ``-M key=value`` then sets a model's field (or one of its
``params``) on every model, ``-M NAME:key=value`` on one. ``--set`` reaches list items by index
(``models.0.temperature=0``). A key that moved into a kind's section keeps its old spelling here
(``--modes``, ``--set max_steps=9`` set ``episodes.modes`` and ``episodes.max_steps``).
"""

from __future__ import annotations

from typing import Any

import yaml
from pydantic import BaseModel, Field

from scratchworld_dist._errors import ConfigError
from scratchworld_dist.sweep._former_keys import Notice, moved_keys, moved_notice
from workers.contract import ModelSpec


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

    model_args: list[str] = Field(default_factory=list)
    """``key=value`` for every model, ``NAME:key=value`` for one (``-M``): a model field (temperature, max_tokens,
    api_base, api_key_env...) or else one of its ``params``; each value read as YAML."""

    sample: str | None = None
    """How ``--limit`` picks its items: ``first`` (suite order) or ``random``: ``tasks.sample``."""

    sample_seed: int | None = None
    """The seed of a random sample: ``tasks.sample_seed``."""

    tags: list[str] = Field(default_factory=list)
    """``key=value`` labels of the run (``--tag``): ``tags``, recorded in the manifest, reports and exports."""

    settings: list[str] = Field(default_factory=list)
    """``dotted.key=value`` assignments, each value read as YAML (``limits.retries=2``, ``drag.types=[T1]``)."""

    values: dict[str, Any] = Field(default_factory=dict)
    """Dotted keys and their values as they are (the Python API's keyword arguments), applied last."""

    @classmethod
    def command_line_fields(cls) -> list[str]:
        """The fields ``run`` and ``plan`` take as options (all but the Python API's ``values``)."""
        return [name for name in cls.model_fields if name != "values"]

    def apply(self, data: dict[str, Any], notice: Notice | None = None) -> dict[str, Any]:
        """``data`` (a config file's mapping) with these changes, the ``--set`` ones last; ``notice`` hears of
        each key given in a former spelling (``max_steps`` for ``episodes.max_steps``)."""
        changed, moved = dict(data), moved_keys()
        if self.models:
            changed["models"] = _chosen_models(data.get("models"), self.models, notice)
        for argument in self.model_args:
            changed["models"] = _with_model_arg(changed.get("models"), argument)
        if self.tasks:
            _assign(changed, ["tasks", "ids"], _split(self.tasks))
        if self.limit is not None:
            _assign(changed, ["tasks", "limit"], self.limit)
        if self.sample is not None:
            _assign(changed, ["tasks", "sample"], self.sample)
        if self.sample_seed is not None:
            _assign(changed, ["tasks", "sample_seed"], self.sample_seed)
        for tag in self.tags:
            key, sep, value = tag.partition("=")
            if not sep or not key.strip():
                raise ConfigError(f"--tag {tag!r}: write it as key=value")
            _assign(changed, ["tags", key.strip()], value.strip())
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


def _chosen_models(entries: Any, wanted: list[str], notice: Notice | None) -> list[Any]:
    """The config's model entries ``wanted`` names (by name or LiteLLM string), whole; any other name a new entry
    with LiteLLM's defaults, which ``notice`` hears of (it takes no other entry's settings: not its endpoint,
    nor its key)."""
    known = [entry for entry in entries or [] if isinstance(entry, dict)]
    chosen: list[Any] = []
    for name in _split(wanted):
        match = [entry for entry in known if name in (entry.get("name"), entry.get("model"))]
        if not match and notice is not None:
            notice(new_model_notice(name))
        chosen += match or [{"model": name}]
    return chosen


def new_model_notice(model: str) -> str:
    """What ``--model`` says of a model the config does not name: the defaults it runs with."""
    return (
        f"notice: model {model} is not in the config; it runs with LiteLLM's defaults: the provider's temperature "
        "and max_tokens, LiteLLM's endpoint and key variable for its provider, no api_key_env (so no probe unless "
        f"--probe); set any of them with -M {model}:key=value"
    )


def _with_model_arg(entries: Any, argument: str) -> list[Any]:
    """``entries`` with ``-M [NAME:]key=value`` applied: a model field, else one of the model's ``params``."""
    head, sep, text = argument.partition("=")
    name, _, key = head.rpartition(":")  # a model's name may hold a colon (ollama/llama3:8b), a key never does
    path = key.strip().split(".")
    if not sep or not all(path):
        raise ConfigError(f"-M {argument!r}: write it as key=value, or NAME:key=value for one model")
    if path[0] not in ModelSpec.model_fields:
        path = ["params", *path]
    try:
        value = yaml.safe_load(text)
    except yaml.YAMLError:
        raise ConfigError(f"-M {head}: the value is not valid YAML") from None
    models = [dict(entry) if isinstance(entry, dict) else entry for entry in entries or []]
    targets = [e for e in models if isinstance(e, dict) and (not name or name in (e.get("name"), e.get("model")))]
    if not targets:
        names = ", ".join(str(e.get("name") or e.get("model")) for e in models if isinstance(e, dict)) or "none"
        raise ConfigError(f"-M {head}: no model {'named ' + name if name else 'to set'} (the models: {names})")
    for entry in targets:
        _assign(entry, path, value, option="-M")
    return models


def _assign(data: dict[str, Any], path: list[str], value: Any, option: str = "--set") -> None:
    """Set ``data[path[0]][path[1]]... = value``, making the mappings on the way; a list's item is reached by its
    index (``models.0.temperature``); a scalar on the way, or an index past the list, is an error."""
    node: Any = data
    for depth, key in enumerate(path):
        where = ".".join(path[:depth])
        if isinstance(node, list):
            if not key.isdigit() or int(key) >= len(node):
                raise ConfigError(
                    f"{option} {'.'.join(path)}: {where} is a list of {len(node)} item(s); "
                    f"give an index from 0 to {len(node) - 1}"
                    if node
                    else f"{option} {'.'.join(path)}: {where} is an empty list"
                )
            index: Any = int(key)
        elif isinstance(node, dict):
            index = key
        else:
            raise ConfigError(f"{option} {'.'.join(path)}: {where} is not a section of the config")
        if depth == len(path) - 1:
            node[index] = value
            return
        child = node[index] if isinstance(node, list) else node.get(key)
        if child is None:
            child = {}
        child = dict(child) if isinstance(child, dict) else list(child) if isinstance(child, list) else child
        node[index] = child
        node = child
