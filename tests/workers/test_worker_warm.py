"""A worker imports LiteLLM while it opens its editors, before its first job, when the sweep's jobs call models:
imported at the first job instead, the import held up every episode of the worker as it started."""

from __future__ import annotations

import subprocess
import sys

import pytest

WARM = """
import asyncio, sys
from workers.actor import JobWorker
asyncio.run(JobWorker(0).warm(0, calls_models={calls}))
print("litellm" in sys.modules)
"""


@pytest.mark.parametrize("calls", [True, False])
def test_warm_imports_litellm_only_for_jobs_that_call_models(calls: bool) -> None:
    # A fresh interpreter: this test process may have imported LiteLLM already.
    done = subprocess.run(
        [sys.executable, "-c", WARM.format(calls=calls)], capture_output=True, text=True, timeout=300, check=True
    )
    assert done.stdout.split()[-1] == str(calls)
