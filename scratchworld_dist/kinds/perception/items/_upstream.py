"""Upstream's visual perception benchmark, read in place from a ScratchWorld clone.

::

    CLONE/visual_perception_benchmark/tasks/<n>.json          {task_id, instruction, screenshot, task_type, tag,
                                                               ground_truth, prompt, response_content, ...}
    CLONE/visual_perception_benchmark/screenshots_final/*.png  the 149 screenshots

Each task file also stores the prompt that *generated* its question (and the generating model's reply);
neither is a prompt to answer it, and both are ignored. Items are named ``vp_<n>`` (zero-padded to three
digits) and ordered by number. An answer of YES or NO makes a yes/no item; any other answer is an exact
value whose kind follows the question's wording (``What number``, ``What text``, ``What option``) and
else upstream's tag. A file that cannot be used is left out with a problem naming it.
"""

from __future__ import annotations

from pathlib import Path

from pydantic import BaseModel, ConfigDict, Field, ValidationError

from scratchworld_dist._errors import validation_summary
from scratchworld_dist.kinds.perception.items._item import PerceptionItem, UpstreamItemInfo
from scratchworld_dist.kinds.perception.items._suite import PerceptionSuite
from scratchworld_dist.suites import SuiteKind, SuiteProblem, SuiteProblems
from workers.agent_api import ValueKind
from workers.kinds.perception import NO, YES, QuestionKind

BENCHMARK_DIR = Path("visual_perception_benchmark")
TASKS_DIR = BENCHMARK_DIR / "tasks"
SCREENSHOTS_DIR = BENCHMARK_DIR / "screenshots_final"

_WORDING: tuple[tuple[str, ValueKind], ...] = (
    ("what number", "number"),
    ("what text", "text"),
    ("what option", "dropdown"),
)


class UpstreamPerceptionTask(BaseModel):
    """The fields of an upstream task file that matter for answering it (the rest is ignored)."""

    model_config = ConfigDict(extra="ignore")

    task_id: str = Field(min_length=1, max_length=40)
    instruction: str = Field(min_length=1)
    screenshot: str = Field(min_length=1, max_length=200)
    task_type: QuestionKind
    tag: str = Field(min_length=1, max_length=80)
    ground_truth: str = Field(min_length=1)
    focus_hint: str | None = None


def value_kind_of(question: str, tag: str) -> ValueKind:
    """What an exact-value item asks for: by the question's first words, else by upstream's tag."""
    opening = question.strip().lower()
    for words, kind in _WORDING:
        if opening.startswith(words):
            return kind
    return "dropdown" if "dropdown" in tag else "number" if "numeric" in tag else "text"


def item_id_of(task_id: str) -> str:
    """``vp_007`` for upstream's task 7 (a non-numeric id is kept after the prefix)."""
    return f"vp_{int(task_id):03d}" if task_id.isdigit() else f"vp_{task_id}"


class UpstreamPerceptionLoader:
    """Loads a clone's ``visual_perception_benchmark``."""

    kind: SuiteKind = "upstream"

    @staticmethod
    def handles(root: Path) -> bool:
        return (root / TASKS_DIR).is_dir() and (root / SCREENSHOTS_DIR).is_dir()

    def load(self, root: Path) -> PerceptionSuite:
        items: list[tuple[int, str, PerceptionItem]] = []
        problems: list[SuiteProblem] = []
        for path in sorted((root / TASKS_DIR).glob("*.json")):
            item, number, problem = self._load_item(root, path)
            if item is None:
                problems.append(problem or SuiteProblem(path=path, message="unreadable"))
                continue
            items.append((int(number) if number.isdigit() else 10**9, number, item))
        seen: set[str] = set()
        ordered: list[PerceptionItem] = []
        for _, _, item in sorted(items, key=lambda entry: entry[:2]):
            if item.id in seen:
                problems.append(SuiteProblem(path=root / TASKS_DIR, message=f"two tasks are item {item.id}"))
                continue
            seen.add(item.id)
            ordered.append(item)
        return PerceptionSuite(
            name="scratchworld-upstream-perception", kind="upstream", root=root, items=tuple(ordered),
            problems=tuple(problems),
        )  # fmt: skip

    def _load_item(self, root: Path, path: Path) -> tuple[PerceptionItem | None, str, SuiteProblem | None]:
        """The item of one task file and upstream's number for it, or the problem that leaves it out."""
        reader = SuiteProblems(root)
        data = reader.read_json(path)
        if data is None:
            return None, "", SuiteProblem(path=path, message=reader.items[0].message)
        try:
            task = UpstreamPerceptionTask.model_validate(data)
        except ValidationError as exc:
            return None, "", SuiteProblem(path=path, message=validation_summary(exc))
        shot = Path(task.screenshot)
        if shot.is_absolute() or len(shot.parts) != 1:
            message = f"screenshot: {task.screenshot!r} is not a file name"
            return None, "", SuiteProblem(path=path, message=message)
        screenshot = root / SCREENSHOTS_DIR / shot
        if not screenshot.is_file():
            return None, "", SuiteProblem(path=path, message=f"screenshot: {screenshot} does not exist")
        answer = task.ground_truth.strip()
        yes_no = answer.upper() in (YES, NO)
        try:
            item = PerceptionItem(
                id=item_id_of(task.task_id),
                kind=task.task_type,
                tag=task.tag,
                question=task.instruction.strip(),
                answer_format="yes_no" if yes_no else "value",
                value_kind=None if yes_no else value_kind_of(task.instruction, task.tag),
                answer=answer.upper() if yes_no else answer,
                screenshot=screenshot,
                upstream=UpstreamItemInfo(task_id=task.task_id, focus_hint=task.focus_hint),
            )
        except ValidationError as exc:
            return None, "", SuiteProblem(path=path, message=validation_summary(exc))
        return item, task.task_id, None
