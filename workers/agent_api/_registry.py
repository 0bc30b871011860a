"""Finding an agent by benchmark kind and name, and building it with validated parameters.

Each benchmark kind whose jobs run agents says where they register (its worker kind's ``agents``, an
``AgentGroup``): ``scratchworld.agents`` for episodes (``tasks``: the group plugins have always used, kept as it
was), ``scratchworld.drag_agents``, ``scratchworld.perception_agents``, or a plugin kind's own group; this registry
keeps no table of kinds. One group per kind, rather than one group with kind-qualified names (``drag.oracle``),
because the same short names (``oracle``, ``llm``) stand for different classes in each benchmark and configs keep
writing them as they are (``agent: oracle`` under ``benchmark: drag``); the group a config's benchmark names is
the only place its names are looked up, so no name can reach an agent of another benchmark. A class also says
which kinds it serves (``kinds``; episode agents without the attribute serve ``tasks``), so an agent named by
``package.module:Class`` or registered in the wrong group is refused with what it serves.

The driver resolves each agent and validates its parameters while loading the sweep config, so an
agent that fails to import or rejects its parameters stops the run before anything starts.
"""

from __future__ import annotations

import hashlib
import importlib
import inspect
import socket
from importlib.metadata import PackageNotFoundError, packages_distributions, version
from pathlib import Path
from typing import Any

from pydantic import BaseModel, ValidationError

from workers import Registry, one_line
from workers.agent_api._agent import NoParams
from workers.contract import AgentRef, AgentUnavailableError, ModelSpec
from workers.kinds import DEFAULT_KIND, AgentGroup, KindRegistryError, agents_of, worker_kinds


def agent_kinds(cls: type) -> tuple[str, ...]:
    """The benchmark kinds ``cls`` serves (``tasks`` for an episode agent that does not say)."""
    return tuple(getattr(cls, "kinds", (DEFAULT_KIND,)))


def registered_agents(kind: str = DEFAULT_KIND) -> list[str]:
    """The names registered for ``kind`` in this environment."""
    return _registry(kind).names()


def agent_class(name: str, kind: str = DEFAULT_KIND) -> type[Any]:
    """The class ``name`` stands for in benchmark ``kind``; raises ``AgentUnavailableError`` saying why it
    cannot be had (not registered for that kind, not importable, or serving other kinds)."""
    registry = _registry(kind)
    if ":" not in name:
        point = registry.points().get(name)
        if point is None:
            raise AgentUnavailableError(_unregistered(name, kind))
        return registry.load(point)
    module_name, _, attribute = name.partition(":")
    try:
        found = getattr(importlib.import_module(module_name), attribute)
    except AttributeError:
        raise AgentUnavailableError(f"agent {name}: module {module_name} has no {attribute}") from None
    except Exception as exc:  # a plugin's import may fail in any way: say how, in one line
        raise AgentUnavailableError(f"agent {name} cannot be imported: {one_line(exc)}") from exc
    problem = registry.check(name, found)
    if problem is not None:
        raise AgentUnavailableError(f"agent {name} {problem}")
    return found


def _agent_groups() -> dict[str, AgentGroup]:
    """Each installed kind that runs agents, with where they register."""
    try:
        kinds = worker_kinds()
    except KindRegistryError as exc:  # a broken plugin kind: one line, as every agent problem
        raise AgentUnavailableError(str(exc)) from exc
    return {name: group for name, kind in kinds.items() if (group := agents_of(kind)) is not None}


def _registry(kind: str) -> Registry[type[Any]]:
    """The agents of ``kind``: its group, each checked against what the kind asks of its agents."""
    groups = _agent_groups()
    if kind not in groups:
        raise AgentUnavailableError(f"no agents serve {kind!r}: the benchmarks are {', '.join(groups)}")
    agents = groups[kind]

    def problem(name: str, found: object) -> str | None:
        if not isinstance(found, type):
            return f"is not a class: see {agents.base}"
        serves = agent_kinds(found)
        if kind not in serves:
            return f"serves {', '.join(serves) or 'no benchmark'}, not {kind}"
        missing = [method for method in agents.methods if not callable(getattr(found, method, None))]
        return f"lacks {', '.join(missing)}: see {agents.base}" if missing else None

    return Registry(agents.group, "agent", AgentUnavailableError, problem)


def _unregistered(name: str, kind: str) -> str:
    """Why ``name`` is no agent of ``kind``: the names that are, and the kinds it is registered for instead."""
    known = ", ".join(registered_agents(kind)) or "none"
    elsewhere = [other for other in _agent_groups() if other != kind and name in registered_agents(other)]
    serves = f"; {name!r} is an agent of {' and '.join(elsewhere)}" if elsewhere else ""
    return (
        f"agent {name!r} is not registered for the {kind} benchmark (registered: {known}){serves}; name an installed "
        "plugin's entry point or package.module:Class (built-in names missing: run ./install.sh again)"
    )


def checked_agent(ref: AgentRef, kind: str = DEFAULT_KIND) -> type[Any]:
    """The class of ``ref`` for ``kind`` once its params validate and it claims no privilege it may not have:
    what the driver checks of every agent a config names."""
    found = agent_class(ref.name, kind)
    agent_params(found, ref)
    if getattr(found, "privileged", False) and agent_code(found) is not None:
        raise AgentUnavailableError(
            f"agent {ref.name} declares privileged = True, which would show it the solution: "
            "only the harness's own oracles may be privileged"
        )
    if getattr(found, "acts_live", False) and agent_code(found) is not None:
        raise AgentUnavailableError(
            f"agent {ref.name} declares acts_live = True, which would hand it the live editor unrecorded: "
            "only the harness's own human agent may act live"
        )
    return found


def is_privileged(cls: type) -> bool:
    """Whether ``cls`` may see the answer: it says so and is the harness's own (a plugin never is)."""
    return bool(getattr(cls, "privileged", False)) and agent_code(cls) is None


def agent_params(cls: type[Any], ref: AgentRef) -> BaseModel:
    """``ref.params`` validated by the agent's own ``Params`` model; a parameter it has no field for is refused."""
    model: type[BaseModel] = getattr(cls, "Params", NoParams)
    known = {name for name, field in model.model_fields.items() for name in (name, field.alias) if name}
    unknown = sorted(set(ref.params) - known)
    if unknown and not known:
        raise AgentUnavailableError(f"agent {ref.name} takes no params (given: {', '.join(unknown)})")
    if unknown:  # even for a Params model that would ignore them: they would name jobs without changing them
        accepted = ", ".join(sorted(model.model_fields)) or "none"
        raise AgentUnavailableError(
            f"agent {ref.name} rejects its params: unknown {', '.join(unknown)} (accepted: {accepted})"
        )
    try:
        return model.model_validate(ref.params)
    except ValidationError as exc:
        problems = "; ".join(
            f"{'.'.join(str(part) for part in error['loc']) or 'params'}: {error['msg']}" for error in exc.errors()
        )
        raise AgentUnavailableError(f"agent {ref.name} rejects its params: {problems}") from None


def extra_models(params: BaseModel) -> list[ModelSpec]:
    """The models an agent calls besides the job's own, as its params name them (``Params.extra_models``)."""
    listed = getattr(params, "extra_models", None)
    if not callable(listed):
        return []
    models = list(listed())
    if not all(isinstance(model, ModelSpec) for model in models):
        raise AgentUnavailableError(f"{type(params).__name__}.extra_models must return ModelSpec instances")
    return models


_HARNESS_DIR = Path(__file__).resolve().parents[1]
"""``workers/``: agents defined here are covered by the harness fingerprint."""


def agent_code(cls: type) -> str | None:
    """A digest of a plugin agent's code (its module's source and its distribution's version), part of
    its jobs' identity; None for agents of the harness itself, which the harness fingerprint covers."""
    source = inspect.getsourcefile(cls)
    if source is None:
        return "unknown"
    path = Path(source).resolve()
    if path.is_relative_to(_HARNESS_DIR):
        return None
    top = cls.__module__.split(".")[0]
    versions = []
    for distribution in packages_distributions().get(top, []):
        try:
            versions.append(f"{distribution}=={version(distribution)}")
        except PackageNotFoundError:
            continue
    digest = hashlib.sha256(path.read_bytes())
    digest.update(",".join(sorted(versions)).encode())
    return digest.hexdigest()[:16]


def code_mismatch(ref: AgentRef, planned: str | None, cls: type) -> str | None:
    """Why a worker must refuse a job whose agent code differs from the one the driver planned it with (None:
    the same). A plugin's code is part of its jobs' identity, so another version must not answer for it."""
    code = agent_code(cls)
    if code == planned:
        return None
    return (
        f"{socket.gethostname()} has agent {ref.name} with code {code}, the job was planned for {planned}: "
        "install the same version here"
    )


def build_agent(ref: AgentRef, kind: str = DEFAULT_KIND) -> Any:
    """A new agent of ``kind`` for one job (an ``Agent`` for an episode), built with its validated params."""
    cls = agent_class(ref.name, kind)
    try:
        return cls(agent_params(cls, ref))  # type: ignore[call-arg]
    except AgentUnavailableError:
        raise
    except Exception as exc:
        raise AgentUnavailableError(f"agent {ref.name} could not be built: {one_line(exc)}") from exc
