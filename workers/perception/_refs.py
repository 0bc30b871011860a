"""The perception agents by name: what the driver validates, without loading anything heavy."""

from __future__ import annotations

from workers.contract import AgentRef, AgentUnavailableError

PERCEPTION_AGENTS = ("oracle", "always_yes", "llm")
"""``oracle`` answers with the item's label (it must score 100%: a miss is a bug in loading or scoring);
``always_yes`` answers YES to everything (it scores the YES share of the set: a floor for models);
``llm`` asks the job's model."""

NEEDS_MODEL = frozenset({"llm"})


def checked_perception_agent(ref: AgentRef) -> None:
    """Raise ``AgentUnavailableError`` naming the problem unless ``ref`` is a perception agent as given."""
    if ref.name not in PERCEPTION_AGENTS:
        raise AgentUnavailableError(
            f"the perception benchmark's agents are {', '.join(PERCEPTION_AGENTS)}, not {ref.name!r}"
        )
    if ref.params:
        raise AgentUnavailableError(f"agent {ref.name} takes no params in the perception benchmark")


def needs_model(ref: AgentRef) -> bool:
    return ref.name in NEEDS_MODEL
