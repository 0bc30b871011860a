"""The ``perception`` kind inside a worker: a question about a stored screenshot, one model call, both scorings;
no editor; and its contract with the driver (``PerceptionSpec``, ``PerceptionPayload``, ``PerceptionAttempt``...;
``QuestionKind`` is what an item asks about: a connection, a block's existence or a field).

The scoring and the prompt are exported here (the reports' comparisons score canned replies with them); the
agents are found through the registry (``workers.agent_api.agent_class(name, "perception")``); the runner
(``run_perception``) needs the model stack, so it is imported on first use.
"""

import typing

import workers
from workers.kinds.perception._contract import (
    NO,
    PERCEPTION_KINDS,
    YES,
    AnswerParse,
    PerceptionAttempt,
    PerceptionPayload,
    PerceptionScore,
    PerceptionSpec,
    QuestionKind,
    answer_problem,
)
from workers.kinds.perception._kind import PERCEPTION, PerceptionKind
from workers.kinds.perception._prompts import perception_messages
from workers.kinds.perception._scoring import score_reply, strict_correct

if typing.TYPE_CHECKING:
    from workers.kinds.perception._runner import run_perception

__getattr__ = workers.lazy_exports(__name__, {"._runner": ("run_perception",)})

__all__ = [
    "NO",
    "PERCEPTION",
    "PERCEPTION_KINDS",
    "YES",
    "AnswerParse",
    "PerceptionAttempt",
    "PerceptionKind",
    "PerceptionPayload",
    "PerceptionScore",
    "PerceptionSpec",
    "QuestionKind",
    "answer_problem",
    "perception_messages",
    "run_perception",
    "score_reply",
    "strict_correct",
]
