"""What the kinds of single answers (drag, perception) share in checking a sweep: they have no memory across
jobs and no synthetic stand-in episodes, which are the task episodes' own."""

from __future__ import annotations

from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from scratchworld_dist.sweep import SweepConfig


def refuse_episode_sections(config: SweepConfig, title: str) -> None:
    """Raise ``ValueError`` when a single-answer sweep names memory or synthetic episodes."""
    if config.memory is not None or config.synthetic is not None:
        raise ValueError(f"memory and synthetic are for task suites, not the {title} benchmark")
