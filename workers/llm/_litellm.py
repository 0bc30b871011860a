"""LiteLLM itself: imported without the network and off the event loop, and what it sends a model.

Importing ``workers.llm`` does not import LiteLLM (2-3 s, and without the bundled cost map the
import goes to the network); these load it on first use.
"""

from __future__ import annotations

import asyncio
import functools
import importlib.metadata
import os
import sys
import threading
from types import ModuleType

_LITELLM_LOCK = threading.Lock()


def _import_litellm() -> ModuleType:
    """Import LiteLLM with the bundled cost map: otherwise the import itself goes to the network."""
    with _LITELLM_LOCK:
        os.environ.setdefault("LITELLM_LOCAL_MODEL_COST_MAP", "True")
        import litellm

        litellm.suppress_debug_info = True  # no "Give Feedback" banners on stdout per error
        return litellm


async def load_litellm() -> ModuleType:
    """LiteLLM, imported off the event loop the first time (the import takes 2-3 s)."""
    module = sys.modules.get("litellm")
    if module is not None and getattr(module, "acompletion", None) is not None:
        return module
    return await asyncio.to_thread(_import_litellm)


async def close_litellm_clients() -> None:
    """Close LiteLLM's cached HTTP sessions (call before the event loop ends, e.g. in test teardown)."""
    if "litellm" in sys.modules:
        await sys.modules["litellm"].close_litellm_async_clients()


@functools.cache
def takes_seed(model: str) -> bool:
    """Whether LiteLLM sends a seed to this model (the client passes the episode's seed only then)."""
    litellm = _import_litellm()
    try:
        return "seed" in (litellm.get_supported_openai_params(model=model) or [])
    except Exception:  # an unknown provider: do not risk a 400 over a seed
        return False


@functools.cache
def litellm_version() -> str:
    """The installed LiteLLM's version (it turns our keywords into the provider's request)."""
    return importlib.metadata.version("litellm")
