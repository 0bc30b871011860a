"""Turning what a script returned into counts and verdicts."""

from __future__ import annotations

import pytest

from workers.evaluation import ReportError, parse_report


def test_full_upstream_report() -> None:
    report = parse_report(
        {
            "success": False,
            "passed_tests": 1,
            "total_tests": 2,
            "partial_success_rate": 0.5,
            "details": [
                {"name": "a", "passed": True, "duration_ms": 12, "timeout": False, "meta": {"x": 1}},
                {"name": "b", "passed": False, "error": "boom", "timeout": True},
            ],
        }
    )
    assert (report.passed, report.total, report.warnings) == (1, 2, [])
    assert report.tests[0].meta == {"x": 1} and report.tests[0].duration_ms == 12
    assert report.tests[1].error == "boom" and report.tests[1].timed_out is True


def test_details_only_report_derives_counts() -> None:
    report = parse_report({"details": [{"name": "a", "passed": True}, {"name": "b", "passed": True}]})
    assert (report.passed, report.total) == (2, 2)


def test_counts_only_report() -> None:
    report = parse_report({"passed_tests": 0, "total_tests": 3})
    assert (report.passed, report.total, report.tests) == (0, 3, [])


def test_disagreements_become_warnings_and_counts_win() -> None:
    report = parse_report(
        {"success": True, "passed_tests": 1, "total_tests": 2, "details": [{"name": "a", "passed": True}]}
    )
    assert (report.passed, report.total) == (1, 2)
    assert any("counts say 1/2" in w for w in report.warnings)
    assert any("claims success=True" in w for w in report.warnings)


@pytest.mark.parametrize(
    ("raw", "message"),
    [
        (None, "returned nothing"),
        ("all good", "returned str"),
        ([{"name": "a", "passed": True}], "returned list"),
        ({}, "neither details nor"),
        ({"details": "yes"}, "details must be a list"),
        ({"details": [1]}, r"details\[0\] must be an object"),
        ({"details": [{"name": "a", "passed": "yes"}]}, r"details\[0\].passed must be true or false"),
        ({"details": []}, "no tests"),
        ({"passed_tests": 1}, "given together"),
        ({"passed_tests": 3, "total_tests": 2}, "exceeds"),
        ({"passed_tests": True, "total_tests": 1}, "non-negative integer"),
        ({"passed_tests": 1.5, "total_tests": 2}, "non-negative integer"),
    ],
)
def test_garbage_is_rejected_with_a_reason(raw, message) -> None:
    with pytest.raises(ReportError, match=message):
        parse_report(raw)
