"""The visual perception QA benchmark inside a worker: one question about one screenshot, answered and scored.

The scoring and the prompt are exported here (the reports' comparisons score canned replies with them); the
agents are found through the registry (``workers.agent_api.agent_class(name, "perception")``, entry points
of ``scratchworld.perception_agents``); the runner (``run_perception``) needs the model stack, so it is
imported on first use.
"""

import typing

import workers
from workers.perception._prompts import perception_messages
from workers.perception._scoring import score_reply, strict_correct

if typing.TYPE_CHECKING:
    from workers.perception._runner import run_perception

__getattr__ = workers.lazy_exports(__name__, {"._runner": ("run_perception",)})

__all__ = ["perception_messages", "run_perception", "score_reply", "strict_correct"]
