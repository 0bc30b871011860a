"""Which model a result row stands for across runs: the LiteLLM model and its sampling parameters, not its label;
and how every report names a row's agent/model (``row_label``).

A row names its model by label (the config entry's ``name``, else its ``model`` string), and labels are
free: two runs may call one model by two names, or one name may stand for two settings. So a row's label
is looked up in its own run's manifest (``config.models``) and the row is keyed by what decides the
answers: the LiteLLM model, temperature, max_tokens and further params. Where the model is served
(``api_base``), the key's name, the rate limits and the coordinate convention are left out on purpose:
the same model served by another host, or paced differently, answers the same questions the same way, and
the coordinate convention is how the harness reads a reply, chosen by the model's name unless set, so it
would split one model's drag and episode runs for no difference in the model.

A label joined by ``+`` (an agent that also calls other models, e.g. ``planner+grounder``) is keyed by all
its models together, so it matches only the same combination; the extra models are looked up among the
config's models, then among the model settings in the agents' params. The agent is part of the key: the
same model driven by another agent is another row. Scripted agents (no model) are keyed by agent alone.
"""

from __future__ import annotations

import json
from collections.abc import Iterator
from typing import Any

from pydantic import BaseModel, ConfigDict, JsonValue, ValidationError

from scratchworld_dist._errors import RunDirError, validation_summary
from scratchworld_dist.kinds import job_kinds
from scratchworld_dist.results import RunManifest
from scratchworld_dist.sweep import NO_MODEL, ModelConfig, stored_section

IDENTITY_FIELDS = ("model", "temperature", "max_tokens", "params")
"""What makes two model settings the same model for the diagnosis."""

_READ_FIELDS = ("model", "name", "temperature", "max_tokens", "params")
"""What is read from a config's model entry: the identity and the label (other keys, old or new, are ignored)."""


class ModelKey(BaseModel):
    """What a diagnosis row stands for: an agent and, unless it is scripted, the identity of its models."""

    model_config = ConfigDict(frozen=True)

    agent: str
    identity: str
    """Canonical JSON of ``components`` ('' for a scripted agent)."""

    @property
    def scripted(self) -> bool:
        return not self.identity


class RowModel(BaseModel):
    """A row's model resolved in its run: the key and what it was called there."""

    model_config = ConfigDict(frozen=True)

    key: ModelKey
    label: str
    """The row's model label (``-`` for a scripted agent)."""

    components: tuple[tuple[str, dict[str, JsonValue]], ...]
    """Each model of the label with its identity (``{"label": ...}`` when the manifest does not name it)."""


class ModelResolver:
    """Resolves the (agent, model label) of one run's rows through that run's manifest."""

    def __init__(self, manifest: RunManifest, where: str) -> None:
        self.where = where
        self.models = dict(_config_models(manifest.config, where))
        self.helpers = dict(_agent_models(manifest.config))
        self.unresolved: set[str] = set()
        """Labels this run names that its manifest does not describe (keyed by label only)."""

    def resolve(self, agent: str, label: str) -> RowModel:
        if label == NO_MODEL:
            return RowModel(key=ModelKey(agent=agent, identity=""), label=label, components=())
        names = [label] if label in self.models or "+" not in label else label.split("+")
        components = tuple((name, self._identity(name, first=i == 0)) for i, name in enumerate(names))
        identity = json.dumps([c for _, c in components], sort_keys=True, separators=(",", ":"))
        return RowModel(key=ModelKey(agent=agent, identity=identity), label=label, components=components)

    def _identity(self, name: str, *, first: bool) -> dict[str, JsonValue]:
        found = self.models.get(name) if first else self.models.get(name, self.helpers.get(name))
        if found is None:
            self.unresolved.add(name)
            return {"label": name}
        return found


def describe(identity: dict[str, JsonValue]) -> list[str]:
    """One model's identity as short ``name=value`` items (temperature as ``T``), for telling rows apart."""
    if "label" in identity:
        return [f"label {identity['label']}"]
    items = [f"model={identity.get('model')}"]
    items.append(f"T={_number(identity.get('temperature'))}")
    items.append(f"max_tokens={_number(identity.get('max_tokens'))}")
    params = identity.get("params")
    if isinstance(params, dict):
        items += [f"{key}={json.dumps(value, sort_keys=True)}" for key, value in sorted(params.items())]
    return items


def _number(value: JsonValue) -> str:
    if value is None:
        return "default"
    return f"{value:g}" if isinstance(value, float) else str(value)


def _config_models(config: dict[str, Any], where: str) -> Iterator[tuple[str, dict[str, JsonValue]]]:
    entries = config.get("models") or []
    if not isinstance(entries, list):
        return
    for index, entry in enumerate(entries):
        if not isinstance(entry, dict):
            continue
        try:
            model = ModelConfig.model_validate({k: entry[k] for k in _READ_FIELDS if k in entry})
        except ValidationError as exc:
            raise RunDirError(f"{where}: config.models[{index}] is not a model: {validation_summary(exc)}") from exc
        spec = model.spec()
        yield spec.name, _identity(spec.identity())


def _agent_models(config: dict[str, Any]) -> Iterator[tuple[str, dict[str, JsonValue]]]:
    """Model settings found in the params of the config's agents (an agent's extra models live there), its
    kinds' sections' ``agents`` included."""
    agents: list[Any] = [config.get("agent")]
    for kind in job_kinds():
        part = stored_section(config, kind.name) if kind.config_section is not None else None
        if isinstance(part, dict) and isinstance(part.get("agents"), list):
            agents += part["agents"]
    for agent in agents:
        if isinstance(agent, dict):
            yield from _model_settings(agent.get("params"))


def _model_settings(value: Any) -> Iterator[tuple[str, dict[str, JsonValue]]]:
    """Each mapping inside ``value`` that reads as a model setting (a ``model`` string and a ``name``)."""
    if isinstance(value, list):
        for item in value:
            yield from _model_settings(item)
    if not isinstance(value, dict):
        return
    if isinstance(value.get("model"), str) and isinstance(value.get("name"), str):
        try:
            spec = ModelConfig.model_validate({k: value[k] for k in _READ_FIELDS if k in value}).spec()
        except ValidationError:
            spec = None
        if spec is not None:
            yield spec.name, _identity(spec.identity())
    for item in value.values():
        yield from _model_settings(item)


def _identity(full: dict[str, Any]) -> dict[str, JsonValue]:
    return {field: full.get(field) for field in IDENTITY_FIELDS}


def row_label(agent: str, model: str) -> str:
    """How reports name an agent/model: scripted agents by agent, LLM agents by their model label."""
    if agent == "llm":
        return model
    return agent if model == "-" else f"{agent}/{model}"
