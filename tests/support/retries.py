"""Second looks at a load-sensitive reference, reported rather than hidden.

A real-clock evaluation can miss a timing window when the machine is loaded (two cores shared by
the suite's two processes and their browsers), so a few tests look again when a real-clock run
disagrees. Each second look is recorded on the test (``user_properties``, so it crosses xdist),
listed in the run's summary (``tests/conftest.py``), and a test fails when more than it states
needed one: a real difference repeats, and a page or clock that drifted often is not load.
"""

from __future__ import annotations

import pytest

PROPERTY = "second looks"
"""The ``user_properties`` name the summary lists."""


class SecondLooks:
    """The second looks one test took; ``at_most`` fails the test past its stated allowance."""

    def __init__(self, item: pytest.Item) -> None:
        self.item = item
        self.notes: list[str] = []

    def took(self, case: str, why: str) -> None:
        """Record one second look at ``case`` (and why the first did not count)."""
        self.notes.append(f"{case}: {why}")
        self.item.user_properties.append((PROPERTY, f"{case}: {why}"))

    def at_most(self, allowed: int, out_of: int, what: str) -> None:
        assert len(self.notes) <= allowed, (
            f"{len(self.notes)} second looks at {out_of} {what} (at most {allowed} allowed): {self.notes}"
        )
