"""One model of a sweep config (``models:``): its LiteLLM model, sampling settings and endpoint, with the key itself
left in the environment; a key written into ``params`` is refused wherever it is nested."""

from __future__ import annotations

import re
from typing import Any

from pydantic import BaseModel, ConfigDict, Field, field_validator, model_validator

from workers.contract import CoordinateSystem, ModelSpec, RateLimits

_ENV_NAME = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*$")
_SECRET_KEYS = {"api_key", "key", "token", "secret", "password", "authorization"}


class ModelConfig(BaseModel):
    """One model of the sweep; the key itself stays in the environment, named by ``api_key_env``."""

    model_config = ConfigDict(extra="forbid")

    model: str = Field(min_length=1)
    name: str | None = None
    temperature: float | None = Field(default=None, ge=0)
    max_tokens: int | None = Field(default=None, gt=0)
    api_base: str | None = None
    api_base_env: str | None = None
    """Name of the environment variable holding the base URL (e.g. SCRATCHWORLD_LLM_BASE_URL), read by workers."""

    api_key_env: str | None = None
    params: dict[str, Any] = Field(default_factory=dict)
    coordinates: CoordinateSystem | None = None
    """Primitive-mode coordinate convention (default: by model name; Qwen-VL 0-1000, UI-TARS smart-resize)."""

    rate_limits: RateLimits | None = None
    """Cluster-wide requests/min, tokens/min and concurrency cap for this model."""

    @field_validator("api_key_env", "api_base_env")
    @classmethod
    def _env_name(cls, value: str | None) -> str | None:
        if value is not None and not _ENV_NAME.match(value):
            raise ValueError("must be the NAME of an environment variable (e.g. OPENAI_API_KEY), not its value")
        return value

    @model_validator(mode="after")
    def _one_base(self) -> ModelConfig:
        if self.api_base is not None and self.api_base_env is not None:
            raise ValueError("give api_base or api_base_env, not both")
        return self

    @field_validator("params")
    @classmethod
    def _no_secrets(cls, value: dict[str, Any]) -> dict[str, Any]:
        secrets = sorted(_secret_keys(value))
        if secrets:
            raise ValueError(f"{', '.join(secrets)} may not appear in a config; use api_key_env")
        return value

    def spec(self) -> ModelSpec:
        return ModelSpec(
            name=self.name or self.model,
            model=self.model,
            temperature=self.temperature,
            max_tokens=self.max_tokens,
            api_base=self.api_base,
            api_base_env=self.api_base_env,
            api_key_env=self.api_key_env,
            params=self.params,
            coordinates=self.coordinates,
            rate_limits=self.rate_limits,
        )


def _secret_keys(value: Any, path: str = "") -> list[str]:
    """Keys that would carry a credential, at any depth (e.g. extra_headers.Authorization)."""
    found: list[str] = []
    if isinstance(value, dict):
        for key, item in value.items():
            where = f"{path}{key}"
            lowered = str(key).lower()
            price = lowered.endswith("_cost_per_token")  # LiteLLM's price of a model it has no price for
            if lowered in _SECRET_KEYS or (lowered.endswith(("api_key", "_token", "-key")) and not price):
                found.append(where)
            found.extend(_secret_keys(item, f"{where}."))
    elif isinstance(value, list):
        for item in value:
            found.extend(_secret_keys(item, path))
    return found
