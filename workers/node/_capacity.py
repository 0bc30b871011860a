"""How many episodes a node can hold: derived from what its editors are measured to cost.

An episode of a model-driven agent spends most of its life waiting for the provider. What such
an episode costs the node is its editor's memory and the CPU its page burns while waiting: a
page on the real clock keeps its VM stepping, one on the virtual clock stands still. Both are
measured on the node with real editors (``workers.editor.measure_editor_cost``), and the browser slots
follow with a safety margin (``derive_slots``). Agents that never wait (the oracle) keep one
episode per core: their pages are busy all the time.
"""

from __future__ import annotations

import math

from pydantic import BaseModel, ConfigDict, Field

from workers.contract import MIB, ClockMode
from workers.node._usage import NodeMemory

CPU_FLOOR_CORES = 0.01
"""The least CPU a waiting episode is assumed to cost: its worker's own bookkeeping, timers, I/O."""

MAX_AUTO_SLOTS = 64
"""An upper bound on derived slots: past it the agents' own steps, not waiting pages, bound the node."""


class EditorCost(BaseModel):
    """What one more editor waiting on its model costs this node, as measured."""

    model_config = ConfigDict(frozen=True)

    clock: ClockMode
    cpu_cores: float = Field(ge=0)
    """Cores one waiting page burns (its VM steps on the real clock; nearly nothing on the virtual one)."""

    pss_bytes: int = Field(ge=0)
    """Marginal proportional set size of one editor (its renderer processes and its share of the rest)."""

    harness: str = ""
    """The harness it was measured with; a new harness is measured again."""

    measured_at: float = 0.0


class SlotDerivation(BaseModel):
    """Browser slots for one node and how they came about (printed at the start of a sweep)."""

    model_config = ConfigDict(frozen=True)

    cores: int
    memory: NodeMemory
    cost: EditorCost
    margin: float
    reserve_bytes: int
    by_cpu: int
    by_memory: int
    slots: int

    def describe(self) -> str:
        return (
            f"{self.slots} browser slot(s): {self.cores} core(s) and "
            f"{self.memory.available_bytes / MIB:.0f} MB available, a waiting editor measured at "
            f"{self.cost.cpu_cores:.3f} core(s) and {self.cost.pss_bytes / MIB:.0f} MB PSS on the {self.cost.clock} "
            f"clock; with a {self.margin:.0%} margin the CPU allows {self.by_cpu}, memory {self.by_memory} "
            f"(after a {self.reserve_bytes / MIB:.0f} MB reserve), at most {MAX_AUTO_SLOTS}"
        )


def derive_slots(
    cost: EditorCost, *, cores: int, memory: NodeMemory, margin: float, reserve_bytes: int
) -> SlotDerivation:
    """The episodes a node may hold at once: the fewer of what its CPU and its memory allow, less a margin."""
    usable = 1.0 - margin
    by_cpu = math.floor(cores * usable / max(cost.cpu_cores, CPU_FLOOR_CORES))
    spare = max(memory.available_bytes - reserve_bytes, 0)
    by_memory = math.floor(spare * usable / cost.pss_bytes) if cost.pss_bytes else MAX_AUTO_SLOTS
    slots = max(1, min(by_cpu, by_memory, MAX_AUTO_SLOTS))
    return SlotDerivation(
        cores=cores,
        memory=memory,
        cost=cost,
        margin=margin,
        reserve_bytes=reserve_bytes,
        by_cpu=by_cpu,
        by_memory=by_memory,
        slots=slots,
    )
