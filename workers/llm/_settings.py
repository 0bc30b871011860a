"""How the ``llm`` agent talks to its model: what it is shown each turn, and how hard calls are tried.

The conversation fields change what a model sees, so they are part of a job's identity; the
retry policy only changes how long failures take and is not.
"""

from __future__ import annotations

from typing import Literal

from pydantic import BaseModel, ConfigDict, Field

from workers.llm._client import RetryPolicy

CoordinateSystem = Literal["pixels", "normalized_1000", "smart_resize"]
"""How a model writes screen positions: page pixels; 0-1000 on both axes (Qwen-VL); or the
28-pixel-grid space a UI-TARS model saw after its image was smart-resized (1288x728 for 1280x720)."""


class LLMSettings(BaseModel):
    """The conversation protocol of the llm agent (defaults: the upstream harness, plus action results)."""

    model_config = ConfigDict(frozen=True, extra="forbid")

    history_messages: int = Field(default=21, ge=1)
    """Messages kept after the system prompt (upstream: 21); the newest observation is always sent."""

    last_screenshot_only: bool = True
    """Send only the newest screenshot; older turns keep their text (upstream ``--use_last_screenshot``)."""

    show_action_result: bool = True
    """Tell the model what its previous action did (success or the error message). The upstream
    harness never did; set false to reproduce the paper's protocol exactly."""

    element_list: bool = True
    """Send the element list with the screenshot in primitive mode (upstream ``--disable_element_list``)."""

    retry: RetryPolicy = Field(default_factory=RetryPolicy)
    """Retries, time bounds and circuit breaker of model calls (not part of job identity)."""

    def identity(self) -> dict[str, object]:
        """The fields that can change a job's result."""
        return self.model_dump(mode="json", exclude={"retry"})
