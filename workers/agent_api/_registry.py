"""Finding an agent by name and building it with validated parameters.

A name is either an entry point of the ``scratchworld.agents`` group (how the built-in agents
are registered, and how an installed plugin package registers its own) or ``package.module:Class``.
The driver resolves the agent and validates its parameters while loading the sweep config, so
an agent that fails to import or rejects its parameters stops the run before anything starts.
"""

from __future__ import annotations

import hashlib
import importlib
import inspect
from importlib.metadata import PackageNotFoundError, entry_points, packages_distributions, version
from pathlib import Path

from pydantic import BaseModel, ValidationError

from workers.agent_api._agent import Agent, NoParams
from workers.contract import AgentRef, AgentUnavailableError, ModelSpec

ENTRY_POINT_GROUP = "scratchworld.agents"

_REQUIRED = ("start", "act", "finish")


def registered_agents() -> list[str]:
    """The names registered under ``scratchworld.agents`` in this environment."""
    return sorted({point.name for point in entry_points(group=ENTRY_POINT_GROUP)})


def agent_class(name: str) -> type[Agent]:
    """The class ``name`` stands for; raises ``AgentUnavailableError`` saying why it cannot be had."""
    if ":" in name:
        module_name, _, attribute = name.partition(":")
        where = name
        try:
            found = getattr(importlib.import_module(module_name), attribute)
        except AttributeError:
            raise AgentUnavailableError(f"agent {name}: module {module_name} has no {attribute}") from None
        except Exception as exc:  # a plugin's import may fail in any way: say how, in one line
            raise AgentUnavailableError(f"agent {name} cannot be imported: {_one_line(exc)}") from exc
    else:
        points = [point for point in entry_points(group=ENTRY_POINT_GROUP) if point.name == name]
        if not points:
            known = ", ".join(registered_agents()) or "none"
            raise AgentUnavailableError(
                f"agent {name!r} is not registered (registered: {known}); name an installed plugin's "
                "entry point or package.module:Class (built-in names missing: run ./install.sh again)"
            )
        where = f"{name} ({points[0].value})"
        try:
            found = points[0].load()
        except Exception as exc:
            raise AgentUnavailableError(f"agent {where} cannot be imported: {_one_line(exc)}") from exc
    if not isinstance(found, type):
        raise AgentUnavailableError(f"agent {where} is not a class: see workers.agent_api.Agent")
    missing = [method for method in _REQUIRED if not callable(getattr(found, method, None))]
    if missing:
        raise AgentUnavailableError(f"agent {where} lacks {', '.join(missing)}: see workers.agent_api.Agent")
    return found


def agent_params(cls: type[Agent], ref: AgentRef) -> BaseModel:
    """``ref.params`` validated by the agent's own ``Params`` model; a parameter it has no field for is refused."""
    model: type[BaseModel] = getattr(cls, "Params", NoParams)
    known = {name for name, field in model.model_fields.items() for name in (name, field.alias) if name}
    unknown = sorted(set(ref.params) - known)
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


def agent_code(cls: type[Agent]) -> str | None:
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


def build_agent(ref: AgentRef) -> Agent:
    """A new agent for one episode."""
    cls = agent_class(ref.name)
    try:
        return cls(agent_params(cls, ref))  # type: ignore[call-arg]
    except AgentUnavailableError:
        raise
    except Exception as exc:
        raise AgentUnavailableError(f"agent {ref.name} could not be built: {_one_line(exc)}") from exc


def _one_line(exc: BaseException) -> str:
    text = " ".join(str(exc).split()) or "no message"
    return f"{type(exc).__name__}: {text[:300]}"
