"""Reading what an evaluation script returned into counts and per-test verdicts.

Upstream scripts return ``{success, passed_tests, total_tests, partial_success_rate, details}``;
some return only ``details: [{name, passed}]``. Explicit counts win over the details (they are
what upstream scored); any disagreement is kept as a warning instead of being silently fixed.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from workers.contract import TestVerdict


class ReportError(ValueError):
    """The returned value is not a test report."""


@dataclass
class TestReport:
    """A script's report, normalised."""

    __test__ = False

    passed: int
    total: int
    tests: list[TestVerdict]
    warnings: list[str] = field(default_factory=list)


def _count(raw: dict[str, Any], key: str) -> int | None:
    value = raw.get(key)
    if value is None:
        return None
    if isinstance(value, bool) or not isinstance(value, int | float) or value != int(value) or value < 0:
        raise ReportError(f"{key} must be a non-negative integer, got {value!r}")
    return int(value)


def _verdict(index: int, item: Any, warnings: list[str]) -> TestVerdict:
    if not isinstance(item, dict):
        raise ReportError(f"details[{index}] must be an object, got {type(item).__name__}")
    if not isinstance(item.get("passed"), bool):
        raise ReportError(f"details[{index}].passed must be true or false, got {item.get('passed')!r}")
    name = item.get("name")
    if not isinstance(name, str) or not name:
        warnings.append(f"details[{index}] has no name")
        name = f"test {index + 1}"
    error = item.get("error")
    duration = item.get("duration_ms")
    timed_out = item.get("timeout")
    return TestVerdict(
        name=name,
        passed=item["passed"],
        error=None if error in (None, "") else (error if isinstance(error, str) else str(error)),
        duration_ms=float(duration) if isinstance(duration, int | float) and not isinstance(duration, bool) else None,
        timed_out=timed_out if isinstance(timed_out, bool) else None,
        meta=item.get("meta"),
    )


def parse_report(raw: Any) -> TestReport:
    """Normalise a script's return value; raise ``ReportError`` when it is not a report."""
    if not isinstance(raw, dict):
        raise ReportError(
            f"the script returned {type(raw).__name__ if raw is not None else 'nothing'}, "
            "expected an object with details or passed_tests/total_tests"
        )
    warnings: list[str] = []
    details = raw.get("details")
    if details is not None and not isinstance(details, list):
        raise ReportError(f"details must be a list, got {type(details).__name__}")
    tests = [_verdict(i, item, warnings) for i, item in enumerate(details or [])]

    passed, total = _count(raw, "passed_tests"), _count(raw, "total_tests")
    if (passed is None) != (total is None):
        raise ReportError("passed_tests and total_tests must be given together")
    if passed is None or total is None:
        if details is None:
            raise ReportError("the report has neither details nor passed_tests/total_tests")
        passed, total = sum(t.passed for t in tests), len(tests)
    elif details is not None and (passed, total) != (sum(t.passed for t in tests), len(tests)):
        warnings.append(
            f"counts say {passed}/{total} but details say {sum(t.passed for t in tests)}/{len(tests)}; counts used"
        )
    if total == 0:
        raise ReportError("the report contains no tests")
    if passed > total:
        raise ReportError(f"passed_tests ({passed}) exceeds total_tests ({total})")

    claimed = raw.get("success")
    if isinstance(claimed, bool) and claimed != (passed == total):
        warnings.append(f"the script claims success={claimed} but {passed}/{total} tests passed")
    return TestReport(passed=passed, total=total, tests=tests, warnings=warnings)
