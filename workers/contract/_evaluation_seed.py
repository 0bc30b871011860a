"""The seed of an evaluation's random numbers, so that a verdict that depends on them repeats.

A test of random behaviour (a sprite that goes to a random place, then checks that it moved far enough)
passes or fails by the numbers ``Math.random`` draws. Drawn from the browser's generator, the same job
could be judged twice and get two verdicts. Every evaluation of a job therefore draws from a seed made of
the job's task and its sweep seed: a rerun, a resume, another machine or page, a regrade all see the same
numbers; the sweep's seeds sample the randomness on purpose (two seeds, two draws). The model, mode and
agent are left out, so that two systems compared on one task and seed are judged under the same draws
(their comparison is paired on task and seed). The agent's page draws from the same seed during its episode.
"""

from __future__ import annotations

import hashlib

from workers.contract._evaluation_spec import EvaluationSpec
from workers.contract._perturbation import MAX_SEED, EvaluationPerturbation


def evaluation_seed(task_id: str, seed: int) -> int:
    """The ``Math.random`` seed of evaluations (and the agent's page) in the job of ``task_id`` at sweep ``seed``."""
    digest = hashlib.sha256(f"scratchworld-evaluation\0{task_id}\0{seed}".encode()).digest()
    return int.from_bytes(digest[:4], "big")


def with_random_seed(spec: EvaluationSpec, seed: int) -> EvaluationSpec:
    """``spec`` whose run draws ``Math.random`` from ``seed``, its other perturbations kept: two runs with one
    seed see the same random numbers."""
    if not 0 <= seed <= MAX_SEED:
        raise ValueError(f"a random seed is from 0 to {MAX_SEED}, got {seed}")
    current = spec.perturbation
    perturbation = (
        current.model_copy(update={"random_seed": seed}) if current else EvaluationPerturbation(random_seed=seed)
    )
    return spec.model_copy(update={"perturbation": perturbation})
