"""Reading the page's note of a run that stopped at its first failing test into the verdict."""

from __future__ import annotations

from workers.contract import EarlyStop
from workers.evaluation import TestReport, parse_report
from workers.evaluation._early_stop import early_stop


def report(*passed: bool) -> TestReport:
    return parse_report({"details": [{"name": f"t{i}", "passed": p} for i, p in enumerate(passed)]})


def test_the_tests_not_run_leave_the_list_and_stay_in_the_counts() -> None:
    stopped = report(True, False, False, False)
    assert early_stop(stopped, {"test": "t1", "notRun": 2}) == EarlyStop(test="t1", not_run=2)
    assert [t.name for t in stopped.tests] == ["t0", "t1"] and (stopped.passed, stopped.total) == (1, 4)
    assert stopped.warnings == []


def test_no_note_is_no_early_stop() -> None:
    full = report(True, False)
    assert early_stop(full, None) is None and len(full.tests) == 2


def test_a_report_that_does_not_end_with_the_tests_not_run_keeps_its_tests() -> None:
    """A script that reports a passing test last (one its helper did not run) is kept as it said, with a warning."""
    odd = report(False, False, True)
    assert early_stop(odd, {"test": "t0", "notRun": 2}) == EarlyStop(test="t0", not_run=2)
    assert len(odd.tests) == 3 and "not run after 't0'" in odd.warnings[0]
    short = report(False)
    assert early_stop(short, {"test": "t0", "notRun": 3}) is not None and len(short.tests) == 1 and short.warnings


def test_a_malformed_note_is_a_warning_not_a_verdict_change() -> None:
    full = report(True, False)
    assert early_stop(full, {"test": "t1", "notRun": 0}) is None
    assert len(full.tests) == 2 and "early stop note" in full.warnings[0]
