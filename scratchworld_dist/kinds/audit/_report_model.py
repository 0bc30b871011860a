"""The audit report's data: per category, task, test and operator, how often the tests fail a wrong program
(mutation score) and pass a correct one written differently (refactoring pass rate), every finding with what
changed and where, and the tasks whose graders judge nothing (vacuous)."""

from __future__ import annotations

from pydantic import BaseModel, JsonValue

from workers.kinds.audit import ShownBy


class Tally(BaseModel):
    mutants: int = 0
    killed: int = 0
    equivalent: int = 0
    outside_task: int = 0
    """Passed every test; differs from the golden only under answers the instruction rules out (not scored)."""

    holes: int = 0
    """Unexplained holes: passed every test, behaves otherwise than the golden in a run the task allows, and no
    declaration of the suite explains the difference."""

    explained: int = 0
    """Holes a declaration explains (a difference the instruction leaves open: not scored)."""

    survived: int = 0
    """Passed every test and could not be traced (counted as holes by the score: a lower bound)."""

    refactorings: int = 0
    passed: int = 0
    brittle: int = 0
    errors: int = 0

    @property
    def mutation_score(self) -> float | None:
        """killed / (killed + unexplained holes): equivalent mutants can be killed by no test, explained holes and
        differences outside the task are no wrong answers, untraced survivors count as holes."""
        decided = self.killed + self.holes + self.survived
        return self.killed / decided if decided else None

    @property
    def refactoring_pass_rate(self) -> float | None:
        decided = self.passed + self.brittle
        return self.passed / decided if decided else None

    def add(self, variant: str, verdict: str, explained: bool = False) -> None:
        if variant == "mutant":
            self.mutants += 1
        else:
            self.refactorings += 1
        field = {"hole": "explained" if explained else "holes", "error": "errors"}.get(verdict, verdict)
        counted = ("killed", "equivalent", "outside_task", "holes", "explained", "survived", "passed", "brittle")
        if field in (*counted, "errors"):
            setattr(self, field, getattr(self, field) + 1)


class TaskAudit(Tally):
    task_id: str
    category: str = ""
    golden_fails: bool = False
    """Its golden fails its own tests: its variants' verdicts measure nothing, and no suite figure counts them."""

    vacuous: str | None = None
    """``never_starts`` (its tests never start the program) or ``observes_nothing`` (they read nothing the golden
    changes): such a grader passes any program, whatever its score says."""


class TestAudit(BaseModel):
    """One test of one task: the mutants it failed, and the refactorings it failed (wrongly)."""

    task_id: str
    test: str
    kills: int
    brittle: int


class Finding(BaseModel):
    """A survivor or a brittle case, with what changed and where."""

    task_id: str
    job_id: str
    operator: str
    target: str
    block_id: str
    description: str
    before: str
    after: str
    failing_tests: list[str]
    observed: str | None
    evidence: str | None
    shown_by: ShownBy | None = None
    """The run that showed ``evidence`` (the tests' own, or an exploration episode) and the stimulus before it."""

    first_difference: dict[str, JsonValue] | None = None
    """``evidence`` as data (frame, target, field, a, b, variable)."""

    explanation: str | None = None
    """The reason a declaration of the suite gives for this hole (an explained hole), with where it is declared."""

    page: str
    """Its job's page in the viewer of these runs (``scratchworld view`` with the runs in this order), relative to
    the viewer's root: ``runs/<k>/jobs/<job_id>.html``. The page shows the golden and the variant side by side."""


class VacuousGrader(BaseModel):
    """A task whose tests judge nothing: they never start the program, or read nothing it changes."""

    task_id: str
    vacuous: str
    """``never_starts`` or ``observes_nothing``."""

    reads: list[tuple[str, str]] = []
    """What its tests read ((target, field); ``*``: any target)."""

    changes: list[tuple[str, str]] = []
    """What the golden changes in its runs."""

    def describe(self) -> str:
        if self.vacuous == "never_starts":
            return "its tests never start the program (no green flag, no script started)"
        read = ", ".join(f"{target}.{field}" for target, field in self.reads) or "nothing"
        return f"its tests read nothing the program changes (they read {read})"


class AuditReport(BaseModel):
    runs: list[str]
    warnings: list[str]
    total: Tally
    mutation_score: float | None
    """killed / (killed + unexplained holes) over the suite (an untraced survivor counts as a hole)."""

    refactoring_pass_rate: float | None
    categories: dict[str, Tally] = {}
    """The same figures per task category (create, debug, ...), over the tasks whose golden passes."""

    vacuous: list[VacuousGrader] = []
    """Tasks whose tests judge nothing (their scores mean nothing either)."""

    tasks: list[TaskAudit]
    tests: list[TestAudit]
    operators: dict[str, Tally]
    holes: list[Finding]
    """Unexplained holes: mutants every test passed whose behaviour differs from the golden's in a run the task
    allows, which no declaration explains (and untraced survivors)."""

    explained: list[Finding] = []
    """Holes a declaration of the suite explains (``explanation`` says why)."""

    outside_task: list[Finding] = []
    """Mutants every test passed that differ only under answers the instruction rules out."""

    equivalent: list[Finding]
    brittle: list[Finding]
