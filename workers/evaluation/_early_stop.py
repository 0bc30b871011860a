"""A run that stopped at its first failing test (``EvaluationSpec.stop_at_first_failure``), read from the page.

The page (``scratch-gui/evaluation/first-failure.js``) returns at once a failed result for every test after the
first that failed, and the script reports those as it reports any failed test, at the end of its details: they
decided nothing and ran nothing, so they are left out of the verdict's tests (still counted in its total).
"""

from __future__ import annotations

from pydantic import BaseModel, ConfigDict, Field, JsonValue, ValidationError

from workers.contract import EarlyStop
from workers.evaluation._report import TestReport


class _Note(BaseModel):
    """The page's ``earlyStop`` note."""

    model_config = ConfigDict(populate_by_name=True)

    test: str
    not_run: int = Field(alias="notRun", ge=1)


def early_stop(report: TestReport, note: JsonValue) -> EarlyStop | None:
    """The early stop the page noted (None without one); the tests that did not run are taken out of ``report``.

    They are the last ones the script reports; a report that does not end with as many failed tests keeps its
    tests as reported, with a warning.
    """
    if note is None:
        return None
    try:
        seen = _Note.model_validate(note)
    except ValidationError as exc:
        report.warnings.append(f"the page's early stop note is not one: {exc.errors()[0]['msg']}")
        return None
    tail = report.tests[-seen.not_run :]
    if len(tail) == seen.not_run and not any(test.passed for test in tail):
        del report.tests[-seen.not_run :]
    else:
        report.warnings.append(
            f"the report does not end with the {seen.not_run} test(s) not run after {seen.test!r}: its tests are kept"
        )
    return EarlyStop(test=seen.test, not_run=seen.not_run)
