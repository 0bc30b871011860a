"""The values and text of diagnosis cells, shared by every kind's columns of the diagnosis table."""

from __future__ import annotations

from pydantic import BaseModel

MISSING = "\u2013"
"""An en dash: the model has no result there (never shown as 0)."""


class Rate(BaseModel):
    """A share and how many runs it is over."""

    value: float
    n: int


def rate_cell(rate: Rate | None) -> str:
    return MISSING if rate is None else f"{pct(rate.value)} (n={rate.n})"


def pct(value: float) -> str:
    return f"{value * 100:.1f}%"


def optional_rate(value: float | None, n: int) -> Rate | None:
    return None if value is None else Rate(value=value, n=n)
