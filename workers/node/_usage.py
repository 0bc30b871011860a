"""What this process's browsers cost the node: memory (PSS) and CPU time of their processes.

Chromium runs as a tree under the Playwright driver, itself a child of the process that
launched it, so a worker finds its own browsers among its descendants and never counts another
worker's. PSS (proportional set size) splits shared pages between the processes that map them,
so the PSS of N editors adds up to what they really take from the node, unlike RSS.
"""

from __future__ import annotations

import psutil
from pydantic import BaseModel, ConfigDict


class BrowserUsage(BaseModel):
    """The browsers under one process at one instant."""

    model_config = ConfigDict(frozen=True)

    processes: int = 0
    renderers: int = 0
    """Processes running pages (Chromium's ``--type=renderer``)."""

    pss_bytes: int = 0
    """Proportional set size of all the browsers' processes."""

    cpu_s: float = 0.0
    """User + system CPU seconds spent so far by the processes alive now."""

    def cpu_cores_since(self, earlier: BrowserUsage, wall_s: float) -> float:
        """Cores used on average between two samples (processes that ended between them are not counted)."""
        return max(self.cpu_s - earlier.cpu_s, 0.0) / wall_s if wall_s > 0 else 0.0


class NodeMemory(BaseModel):
    """The node's memory as the kernel reports it (``MemAvailable``: what can be taken without swapping)."""

    model_config = ConfigDict(frozen=True)

    total_bytes: int
    available_bytes: int


def node_memory() -> NodeMemory:
    memory = psutil.virtual_memory()
    return NodeMemory(total_bytes=memory.total, available_bytes=memory.available)


def browser_usage(root_pid: int | None = None) -> BrowserUsage:
    """Sum over the Chromium processes from ``root_pid`` down (this process by default; a browser
    process's pid gives that one browser, whatever else this process runs)."""
    try:
        root = psutil.Process(root_pid)
        processes_down = [root, *root.children(recursive=True)]
    except psutil.Error:
        return BrowserUsage()
    processes = renderers = pss = 0
    cpu = 0.0
    for process in processes_down:
        try:
            with process.oneshot():
                if "chrom" not in process.name():
                    continue
                is_renderer = "--type=renderer" in process.cmdline()
                pss += process.memory_full_info().pss
                times = process.cpu_times()
        except psutil.Error:  # it ended, or is not ours to read
            continue
        processes += 1
        renderers += is_renderer
        cpu += times.user + times.system
    return BrowserUsage(processes=processes, renderers=renderers, pss_bytes=pss, cpu_s=cpu)
