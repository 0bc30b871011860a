"""How many episodes a node can hold: derived from what its editors are measured to cost.

An episode of a model-driven agent spends most of its life waiting for the provider. What such
an episode costs the node is its editor's memory and the CPU its page burns while waiting: a
page on the real clock keeps its VM stepping, one on the virtual clock stands still. Both are
measured on the node with real editors (``workers.editor.measure_editor_cost``), and the browser slots
follow with a safety margin (``derive_slots``), but never past what the node delivers: the episodes per
core at which ``benchmarks/density.py`` measured steps still undelayed, in the jobs' mode
(``delivered_per_core``: a primitive step drags and screenshots, a composite one calls the API). Waiting
pages alone would allow far more, and the episodes' own work (starting, stepping, ending, being judged)
then delays every step: 64 on 2 cores ran their steps up to seconds late.
Agents that never wait (the oracle) keep one episode per core: their pages are busy all the time.
"""

from __future__ import annotations

import math

from pydantic import BaseModel, ConfigDict, Field

from workers.contract import MIB, ClockMode, Mode
from workers.node._usage import NodeMemory

CPU_FLOOR_CORES = 0.01
"""The least CPU a waiting episode is assumed to cost: its worker's own bookkeeping, timers, I/O."""

DELIVERED_PER_CORE = 32
"""Episodes per core a node holds with their steps undelayed, as ``benchmarks/density.py`` measured them on
2 cores (virtual clock, a model answering after 5 s, 20 steps, ``--n 1,64 --repeat 3``): at N = 64 the step
overhead p50 was 0.07-0.09 s against 0.07 s alone and the steady steps' p95 0.12-0.74 s, 0 errors, three or four
runs in a row on each of the machine's hosts, the faster (2026-12-05), the slower (2026-12-06) and the slowest
(2026-12-07, an editor's opening 1.8-2.2 CPU-s). It was 16 until then: on 2026-12-02 N = 64 had a p50 of 0.28 s
and a steady p95 of 2.0 s. Past it the agents' own work, not their waiting pages, binds the node;
``limits.browser_slots`` sets more where a node was measured to hold them."""

PRIMITIVE_DELIVERED_PER_CORE = 2
"""The same for primitive-mode episodes, whose every step takes a screenshot, reads the element list (OCR where
the DOM has no text) and moves a real mouse through a drag's frames, about 0.8 CPU-s of the browser's per step
against a composite step's few hundredths (``benchmarks/density.py --mode primitive``, 2026-12-02, 2 cores): at N = 4
the step overhead p50 was 1.58 s against 0.84 s alone, at N = 8 2.29 s and at N = 16 4-6 s."""


def delivered_per_core(mode: Mode) -> int:
    """Episodes per core the node holds with their steps undelayed in ``mode``."""
    return PRIMITIVE_DELIVERED_PER_CORE if mode == "primitive" else DELIVERED_PER_CORE


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
    mode: Mode = "composite"
    """The episodes' mode (primitive if any job's is): what they deliver per core depends on it."""
    margin: float
    reserve_bytes: int
    by_cpu: int
    by_memory: int
    by_throughput: int
    """What the node delivers: ``delivered_per_core(mode)`` per core (measured, so no margin)."""
    slots: int

    def describe(self) -> str:
        return (
            f"{self.slots} browser slot(s): {self.cores} core(s) and "
            f"{self.memory.available_bytes / MIB:.0f} MB available, a waiting editor measured at "
            f"{self.cost.cpu_cores:.3f} core(s) and {self.cost.pss_bytes / MIB:.0f} MB PSS on the {self.cost.clock} "
            f"clock; with a {self.margin:.0%} margin the CPU allows {self.by_cpu}, memory {self.by_memory} "
            f"(after a {self.reserve_bytes / MIB:.0f} MB reserve), throughput {self.by_throughput} "
            f"({delivered_per_core(self.mode)} per core in {self.mode} mode, measured by benchmarks/density.py)"
        )


def derive_slots(
    cost: EditorCost,
    *,
    cores: int,
    memory: NodeMemory,
    margin: float,
    reserve_bytes: int,
    mode: Mode = "composite",
) -> SlotDerivation:
    """The episodes of ``mode`` a node may hold at once: the fewest of what its CPU and its memory allow, less a
    margin, and of what it delivers."""
    usable = 1.0 - margin
    by_cpu = math.floor(cores * usable / max(cost.cpu_cores, CPU_FLOOR_CORES))
    spare = max(memory.available_bytes - reserve_bytes, 0)
    by_throughput = cores * delivered_per_core(mode)
    by_memory = math.floor(spare * usable / cost.pss_bytes) if cost.pss_bytes else by_throughput
    slots = max(1, min(by_cpu, by_memory, by_throughput))
    return SlotDerivation(
        cores=cores,
        memory=memory,
        cost=cost,
        mode=mode,
        margin=margin,
        reserve_bytes=reserve_bytes,
        by_cpu=by_cpu,
        by_memory=by_memory,
        by_throughput=by_throughput,
        slots=slots,
    )
