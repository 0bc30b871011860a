"""The two statistics of a paired comparison, from SciPy: a task-clustered bootstrap and McNemar's exact test."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from pydantic import BaseModel

CONFIDENCE = 0.95


class Interval(BaseModel):
    """A percentile bootstrap interval of a paired difference."""

    low: float
    high: float
    confidence: float
    resamples: int
    seed: int
    """Seed of the resampling, so the same results give the same interval."""


class McNemar(BaseModel):
    """Exact McNemar test on paired pass/fail outcomes: do the discordant pairs lean one way?"""

    both_passed: int
    only_a: int
    """Pairs A passed and B failed."""

    only_b: int
    neither: int
    p_value: float
    """Two-sided: ``binomtest(only_a, only_a + only_b, 0.5)``; 1 when no pair is discordant."""


def paired_bootstrap(clusters: Sequence[Sequence[tuple[float, float]]], *, resamples: int, seed: int) -> Interval:
    """Interval of mean(a) - mean(b) over all pairs, resampling whole clusters (tasks) with replacement.

    Each task contributes the sum of its differences and its number of pairs, so a resampled
    statistic is the pooled mean difference of the drawn tasks, as the point estimate is.
    """
    sums = np.array([sum(a - b for a, b in cluster) for cluster in clusters], dtype=float)
    counts = np.array([len(cluster) for cluster in clusters], dtype=float)
    ratios = sums / counts
    if np.allclose(ratios, ratios[0]):  # every resample gives the same value: the interval is that point
        point = float(sums.sum() / counts.sum())
        return Interval(low=point, high=point, confidence=CONFIDENCE, resamples=resamples, seed=seed)
    from scipy import stats  # SciPy's import takes most of a second: paid by the commands that compare

    result = stats.bootstrap(
        (sums, counts),
        _pooled_mean,
        paired=True,
        vectorized=True,
        n_resamples=resamples,
        confidence_level=CONFIDENCE,
        method="percentile",
        rng=np.random.default_rng(seed),
    )
    low, high = result.confidence_interval
    return Interval(low=float(low), high=float(high), confidence=CONFIDENCE, resamples=resamples, seed=seed)


def _pooled_mean(sums: np.ndarray, counts: np.ndarray, axis: int = -1) -> np.ndarray:
    return sums.sum(axis=axis) / counts.sum(axis=axis)


def mcnemar_exact(pairs: Sequence[tuple[float, float]]) -> McNemar:
    """McNemar's exact test over (a passed, b passed) pairs of 0/1 values."""
    both = sum(a == 1 and b == 1 for a, b in pairs)
    only_a = sum(a == 1 and b == 0 for a, b in pairs)
    only_b = sum(a == 0 and b == 1 for a, b in pairs)
    discordant = only_a + only_b
    from scipy import stats

    p_value = float(stats.binomtest(only_a, discordant, 0.5).pvalue) if discordant else 1.0
    return McNemar(
        both_passed=both, only_a=only_a, only_b=only_b, neither=len(pairs) - both - discordant, p_value=p_value
    )
