"""Episodes: an agent acting in an environment until it stops, then the evaluation."""

from workers.episode._environment import CompositeEnvironment, Environment, PrimitiveEnvironment
from workers.episode._regrade import judged, regrade
from workers.episode._runner import EpisodeRunner
from workers.episode._synthetic import run_synthetic

__all__ = [
    "CompositeEnvironment",
    "Environment",
    "EpisodeRunner",
    "PrimitiveEnvironment",
    "judged",
    "regrade",
    "run_synthetic",
]
