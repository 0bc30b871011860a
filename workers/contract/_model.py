"""Models and how they are called: which model, the conversation protocol, retries and cluster budgets.

The fields that change what a model sees or answers are part of a job's identity; the retry
policy and the rate limits only change how long failures take and are not.
"""

from __future__ import annotations

from pathlib import Path
from typing import Literal

from pydantic import BaseModel, ConfigDict, Field, JsonValue

CoordinateSystem = Literal["pixels", "normalized_1000", "smart_resize"]
"""How a model writes screen positions: page pixels; 0-1000 on both axes (Qwen-VL); or the
28-pixel-grid space a UI-TARS model saw after its image was smart-resized (1288x728 for 1280x720)."""


class RetryPolicy(BaseModel):
    """How hard to try one model call, and when to stop calling a failing model at all."""

    model_config = ConfigDict(frozen=True, extra="forbid")

    max_attempts: int = Field(default=6, ge=1)
    initial_backoff_s: float = Field(default=1.0, ge=0)
    max_backoff_s: float = Field(default=60.0, ge=0)
    """Cap of the exponential backoff; each wait is uniform in [0, min(cap, initial * 2**n)]."""

    max_retry_after_s: float = Field(default=120.0, ge=0)
    """Cap on a provider's ``Retry-After``."""

    max_total_s: float = Field(default=600.0, gt=0)
    """Wall-clock bound of one ``complete`` call, waits and attempts included."""

    request_timeout_s: float = Field(default=300.0, gt=0)
    breaker_failures: int = Field(default=5, ge=1)
    """Failed calls (retries exhausted) within ``breaker_window_s`` that open the model's circuit."""

    breaker_window_s: float = Field(default=300.0, gt=0)
    breaker_cooldown_s: float = Field(default=60.0, ge=0)


class RateLimits(BaseModel):
    """The budgets one model (one key and endpoint) may use across the whole cluster."""

    model_config = ConfigDict(frozen=True, extra="forbid")

    requests_per_minute: int | None = Field(default=None, gt=0)
    tokens_per_minute: int | None = Field(default=None, gt=0)
    """Prompt plus completion tokens; a call is charged its estimate, then corrected to its usage."""

    max_concurrency: int = Field(default=8, ge=1)
    """Upper bound of the AIMD window: calls in flight at once."""

    burst_s: float = Field(default=1.0, gt=0)
    """Seconds' worth of each per-minute budget that may go out at once; providers enforce per-minute
    limits at a finer grain, so a full minute's burst invites 429s."""

    lease_s: float = Field(default=900.0, gt=0)
    """A slot not released within this long is reclaimed (its holder crashed or was lost)."""


class ModelSpec(BaseModel):
    """A model as LiteLLM addresses it, with the parameters that change its answers."""

    model_config = ConfigDict(frozen=True, extra="forbid")

    name: str
    """Label used in reports (defaults to the LiteLLM model string)."""

    model: str
    """LiteLLM model string, e.g. ``openai/gpt-4o``."""

    temperature: float | None = None
    max_tokens: int | None = Field(default=None, gt=0)
    api_base: str | None = None
    api_key_env: str | None = None
    """Name of the environment variable that holds the key on the worker; never the key."""

    api_base_env: str | None = None
    """Name of the environment variable that holds the base URL on the worker (e.g. a vLLM server)."""

    params: dict[str, JsonValue] = Field(default_factory=dict)
    """Further LiteLLM keyword arguments (e.g. ``top_p``)."""

    coordinates: CoordinateSystem | None = None
    """How the model writes screen positions in primitive mode; None: chosen by the model's name."""

    rate_limits: RateLimits | None = None
    """Cluster-wide budgets for this model (not part of a job's identity)."""

    def identity(self) -> dict[str, object]:
        """The fields that can change a job's result (labels, key names and pacing cannot)."""
        return self.model_dump(mode="json", exclude={"name", "api_key_env", "rate_limits"})


class ModelCacheSettings(BaseModel):
    """The sweep's opt-in model-call cache: successful replies stored by request, replayed at no cost.

    Not part of a job's identity: a replayed reply is the one this model gave to this exact request
    under this seed (the key covers all of it), so it names the same conditions the job id does.
    """

    model_config = ConfigDict(frozen=True, extra="forbid")

    dir: Path
    """The cache folder, the same absolute path on every node (a shared filesystem shares it)."""


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
