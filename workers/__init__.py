"""What runs inside a worker, and the contract it shares with the driver.

- ``contract``: the data and errors that cross between driver and worker (pydantic and stdlib
  only: the driver, reports and plugins import it without a browser stack);
- ``editor``: Chromium, the served editor files, editor pages and their pool;
- ``evaluation``: a project and a task's script in a clean editor, to a verdict;
- ``composite`` and ``primitive``: the two modes' observations and actions;
- ``agents``, ``llm``, ``ocr``: who acts, how models are called, how text is read off the screen;
- ``episode``: an agent in an environment, then the evaluation, and the Ray actor that runs them;
- ``node``: this machine's installation, harness fingerprint and self-description.

``lazy_exports`` lets a package (here or on the driver) export its browser-stack names without importing them;
``Registry`` is the one entry-point loader behind the driver's kinds, the worker's kinds and the agents.
"""

from workers._lazy import lazy_exports
from workers._registry import PLUGIN_RANK, Registry, one_line

__all__ = ["PLUGIN_RANK", "Registry", "lazy_exports", "one_line"]
