"""Episodes: an agent acting in an environment until it stops, then the evaluation; and the Ray actor that runs them."""

from workers.episode._actor import EpisodeWorker
from workers.episode._environment import CompositeEnvironment, Environment, PrimitiveEnvironment
from workers.episode._runner import EpisodeRunner
from workers.episode._synthetic import run_synthetic

__all__ = [
    "CompositeEnvironment",
    "Environment",
    "EpisodeRunner",
    "EpisodeWorker",
    "PrimitiveEnvironment",
    "run_synthetic",
]
