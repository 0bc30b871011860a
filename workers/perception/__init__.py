"""The visual perception QA benchmark inside a worker: one question about one screenshot, answered and scored.

The scoring and the prompt are exported here (the reports' comparisons score canned replies with them); the
agents are found through the registry (``workers.agent_api.agent_class(name, "perception")``, entry points
of ``scratchworld.perception_agents``), and the runner (``workers.perception._runner``) is imported where
jobs run.
"""

from workers.perception._prompts import perception_messages
from workers.perception._scoring import score_reply, strict_correct

__all__ = ["perception_messages", "score_reply", "strict_correct"]
