"""Benchmark metrics as pure functions: pass@k, pass^k, a mean with its 95% interval, and class counts.

pass@k and pass^k use the unbiased estimators over ``n`` samples of a task of which ``c``
passed (Chen et al. 2021 for pass@k; its all-``k``-succeed twin for pass^k), averaged over
tasks. Tasks with fewer than ``k`` samples cannot be estimated at that ``k`` and are left out
of the average rather than guessed.
"""

from __future__ import annotations

import math
from collections import Counter
from collections.abc import Iterable, Sequence

from pydantic import BaseModel, ConfigDict


class MeanInterval(BaseModel):
    """A mean and the half-width of its 95% t interval (``None`` from a single value)."""

    model_config = ConfigDict(frozen=True)

    mean: float
    half_width: float | None
    """``mean ± half_width`` is the interval; it is not clipped to [0, 1]."""

    n: int
    """Number of values averaged."""


def pass_at_k(n: int, c: int, k: int) -> float:
    """Chance that at least one of ``k`` samples drawn without replacement from ``n`` passes."""
    _check(n, c, k)
    if n - c < k:
        return 1.0
    return 1.0 - math.comb(n - c, k) / math.comb(n, k)


def pass_hat_k(n: int, c: int, k: int) -> float:
    """Chance that all ``k`` samples drawn without replacement from ``n`` pass (pass^k)."""
    _check(n, c, k)
    return math.comb(c, k) / math.comb(n, k)


def mean_pass_at_k(counts: Sequence[tuple[int, int]], k: int) -> float | None:
    """pass@k averaged over the tasks (``(n, c)`` each) that have at least ``k`` samples."""
    values = [pass_at_k(n, c, k) for n, c in counts if n >= k]
    return sum(values) / len(values) if values else None


def mean_pass_hat_k(counts: Sequence[tuple[int, int]], k: int) -> float | None:
    """pass^k averaged over the tasks (``(n, c)`` each) that have at least ``k`` samples."""
    values = [pass_hat_k(n, c, k) for n, c in counts if n >= k]
    return sum(values) / len(values) if values else None


def t_quantile_975(df: int) -> float:
    """Student's t quantile for a two-sided 95% interval with ``df`` degrees of freedom (SciPy's, exact;
    plain 1.96 would understate the interval over a few seeds)."""
    if df < 1:
        raise ValueError(f"degrees of freedom must be at least 1, got {df}")
    from scipy import stats  # SciPy's import takes most of a second: paid by the reports that need it

    return float(stats.t.ppf(0.975, df))


def mean_interval(values: Sequence[float]) -> MeanInterval:
    """Mean of ``values`` with a 95% t interval from their sample standard deviation."""
    if not values:
        raise ValueError("mean_interval needs at least one value")
    n = len(values)
    mean = sum(values) / n
    if n == 1:
        return MeanInterval(mean=mean, half_width=None, n=1)
    variance = sum((v - mean) ** 2 for v in values) / (n - 1)
    return MeanInterval(mean=mean, half_width=t_quantile_975(n - 1) * math.sqrt(variance / n), n=n)


def _check(n: int, c: int, k: int) -> None:
    if not 0 <= c <= n or not 1 <= k <= n:
        raise ValueError(f"need 0 <= c <= n and 1 <= k <= n, got n={n}, c={c}, k={k}")


class ClassCount(BaseModel):
    """How many runs had one error class or one parse failure."""

    name: str
    runs: int


def class_counts(names: Iterable[str]) -> list[ClassCount]:
    """Each name and how often it occurs, most frequent first (ties by name)."""
    return [ClassCount(name=name, runs=n) for name, n in sorted(Counter(names).items(), key=lambda i: (-i[1], i[0]))]
