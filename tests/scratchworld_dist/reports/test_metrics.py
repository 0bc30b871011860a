"""The report core's metrics: pass@k and pass^k (unbiased estimators, averaged over tasks), the t quantile and the
mean with its 95% interval."""

from __future__ import annotations

import itertools
import math

import pytest

from scratchworld_dist.reports import (
    mean_interval,
    mean_pass_at_k,
    mean_pass_hat_k,
    pass_at_k,
    pass_hat_k,
    t_quantile_975,
)


def _brute(n: int, c: int, k: int, every: bool) -> float:
    """Exact pass@k / pass^k by enumerating every k-subset of n samples (c of them passing)."""
    samples = [True] * c + [False] * (n - c)
    subsets = list(itertools.combinations(samples, k))
    hits = sum((all if every else any)(s) for s in subsets)
    return hits / len(subsets)


@pytest.mark.parametrize(
    ("n", "c", "k"), [(n, c, k) for n in range(1, 7) for c in range(n + 1) for k in range(1, n + 1)]
)
def test_estimators_match_enumeration(n: int, c: int, k: int) -> None:
    assert pass_at_k(n, c, k) == pytest.approx(_brute(n, c, k, every=False))
    assert pass_hat_k(n, c, k) == pytest.approx(_brute(n, c, k, every=True))


def test_estimator_known_values() -> None:
    assert pass_at_k(10, 3, 1) == pytest.approx(0.3)
    assert pass_at_k(4, 2, 2) == pytest.approx(5 / 6)
    assert pass_hat_k(4, 2, 2) == pytest.approx(1 / 6)
    assert pass_at_k(5, 0, 3) == 0.0 and pass_at_k(5, 5, 3) == 1.0


@pytest.mark.parametrize(("n", "c", "k"), [(3, 4, 1), (3, -1, 1), (3, 1, 0), (3, 1, 4)])
def test_estimators_reject_impossible_counts(n: int, c: int, k: int) -> None:
    with pytest.raises(ValueError, match="need 0 <= c <= n"):
        pass_at_k(n, c, k)
    with pytest.raises(ValueError, match="need 0 <= c <= n"):
        pass_hat_k(n, c, k)


def test_task_averages_skip_tasks_with_too_few_samples() -> None:
    counts = [(3, 2), (2, 0), (1, 1)]
    assert mean_pass_at_k(counts, 1) == pytest.approx((2 / 3 + 0 + 1) / 3)
    assert mean_pass_at_k(counts, 2) == pytest.approx((1 + 0) / 2)
    assert mean_pass_hat_k(counts, 2) == pytest.approx((1 / 3 + 0) / 2)
    assert mean_pass_at_k(counts, 3) == pytest.approx(1.0)
    assert mean_pass_at_k(counts, 4) is None and mean_pass_hat_k([], 1) is None


@pytest.mark.parametrize(
    ("df", "expected"),
    [(1, 12.7062047), (2, 4.3026527), (10, 2.2281389), (30, 2.0422725), (31, 2.0395134), (120, 1.9799304)],
)
def test_t_quantile(df: int, expected: float) -> None:
    assert t_quantile_975(df) == pytest.approx(expected, abs=1e-7)


def test_t_quantile_decreases_towards_normal() -> None:
    values = [t_quantile_975(df) for df in range(1, 500)]
    assert all(a > b for a, b in itertools.pairwise(values))
    assert values[-1] > 1.96
    with pytest.raises(ValueError, match="at least 1"):
        t_quantile_975(0)


def test_mean_interval() -> None:
    single = mean_interval([0.25])
    assert (single.mean, single.half_width, single.n) == (0.25, None, 1)
    three = mean_interval([1.0, 2.0, 3.0])  # sample sd 1
    assert three.mean == pytest.approx(2.0)
    assert three.half_width == pytest.approx(4.3026527 / math.sqrt(3))
    assert mean_interval([0.5, 0.5]).half_width == 0.0
    with pytest.raises(ValueError, match="at least one"):
        mean_interval([])
