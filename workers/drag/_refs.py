"""The drag agents by name and their parameters: what the driver validates, without the browser stack."""

from __future__ import annotations

from pydantic import BaseModel, ConfigDict, Field, ValidationError

from workers.contract import AgentRef, AgentUnavailableError

DRAG_AGENTS = ("oracle", "jitter", "llm")
NEEDS_MODEL = frozenset({"llm"})


class JitterParams(BaseModel):
    model_config = ConfigDict(extra="forbid")

    sigma_px: float = Field(default=8.0, gt=0, le=200)
    """Standard deviation of the noise on each coordinate of each point, in page px."""


def checked_drag_agent(ref: AgentRef) -> JitterParams | None:
    """``ref``'s parameters, validated (``AgentUnavailableError`` names the problem); None for agents without any."""
    if ref.name not in DRAG_AGENTS:
        raise AgentUnavailableError(f"the drag benchmark's agents are {', '.join(DRAG_AGENTS)}, not {ref.name!r}")
    if ref.name == "jitter":
        try:
            return JitterParams.model_validate(ref.params)
        except ValidationError as exc:
            problems = "; ".join(f"{'.'.join(map(str, e['loc']))}: {e['msg']}" for e in exc.errors())
            raise AgentUnavailableError(f"agent jitter: {problems}") from None
    if ref.params:
        raise AgentUnavailableError(f"agent {ref.name} takes no params in the drag benchmark")
    return None


def needs_model(ref: AgentRef) -> bool:
    return ref.name in NEEDS_MODEL
