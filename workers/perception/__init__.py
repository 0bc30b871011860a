"""The visual perception QA benchmark inside a worker: one question about one screenshot, answered and scored.

The agents' names, the scoring and the prompt are imported with the package (the driver validates configs and
the reports' comparisons score canned replies with them); the runner (``run_perception``) needs the model
stack, so it is imported on first use.
"""

import typing

import workers
from workers.perception._prompts import perception_messages
from workers.perception._refs import PERCEPTION_AGENTS, checked_perception_agent, needs_model
from workers.perception._scoring import score_reply, strict_correct

if typing.TYPE_CHECKING:
    from workers.perception._runner import run_perception

__getattr__ = workers.lazy_exports(__name__, {"._runner": ("run_perception",)})

__all__ = [
    "PERCEPTION_AGENTS",
    "checked_perception_agent",
    "needs_model",
    "perception_messages",
    "run_perception",
    "score_reply",
    "strict_correct",
]
