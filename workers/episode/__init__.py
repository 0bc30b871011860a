"""Episodes: an agent acting in an environment until it stops, then the evaluation; and the Ray actor that runs them."""

from workers.episode._actor import EpisodeWorker
from workers.episode._environment import CompositeEnvironment, Environment, Observation, PrimitiveEnvironment
from workers.episode._runner import EpisodeRunner
from workers.episode._synthetic import run_synthetic

__all__ = [
    "CompositeEnvironment",
    "Environment",
    "EpisodeRunner",
    "EpisodeWorker",
    "Observation",
    "PrimitiveEnvironment",
    "run_synthetic",
]
