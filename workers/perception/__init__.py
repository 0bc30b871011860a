"""The visual perception QA benchmark inside a worker: one question about one screenshot, answered and scored.

Only the agents' names, the scoring and the prompt are exported here (the driver validates configs and the
reports' comparisons score canned replies with them); the runner (``workers.perception._runner``) is
imported where jobs run.
"""

from workers.perception._prompts import perception_messages
from workers.perception._refs import PERCEPTION_AGENTS, checked_perception_agent, needs_model
from workers.perception._scoring import score_reply, strict_correct

__all__ = [
    "PERCEPTION_AGENTS",
    "checked_perception_agent",
    "needs_model",
    "perception_messages",
    "score_reply",
    "strict_correct",
]
