"""A task's exploration plan, made from its golden's hat blocks and its instruction alone: what it does to the
program, which answers it gives and under which seeds, which answers the task allows; the same inputs make the
same plan, and the plan names every job of its task (another plan, other job ids)."""

from __future__ import annotations

from pathlib import Path

from scratchworld_dist.kinds.audit import AuditSweep, audit_jobs
from scratchworld_dist.kinds.audit._declarations import TaskDeclarations
from scratchworld_dist.kinds.audit._exploration import (
    SEEDS,
    answer_domain_from,
    exploration_plan,
    instruction_answers,
    program_inputs,
)
from scratchworld_dist.kinds.audit._plan import DEFAULT_AGENT
from scratchworld_dist.kinds.tasks import read_task
from scratchworld_dist.sb3 import Project, backdrop_costume, block, circle_costume
from scratchworld_dist.suites import load_suite
from tests.conftest import SUITE_DIR
from workers.contract import ProjectLimits
from workers.kinds.audit import Stimulus


def listening(asks: bool = False) -> dict:
    """A project with every kind of hat the exploration answers to (and a ``key pressed?`` block)."""
    project = Project()
    project.stage.costumes.append(backdrop_costume("night"))
    project.stage.script(block("event_whenstageclicked"), block("looks_nextbackdrop"))
    project.stage.script(block("event_whenbackdropswitchesto", BACKDROP="night"), block("looks_nextbackdrop"))
    cat = project.sprite("Cat", costume=circle_costume("a", 10, "#36c"))
    flag = [block("sensing_askandwait", QUESTION="n?")] if asks else []
    cat.script(
        block("event_whenflagclicked"),
        *flag,
        block("control_forever", SUBSTACK=[block("control_if", CONDITION=block("sensing_keypressed", KEY_OPTION="a"),
                                                  SUBSTACK=[block("motion_movesteps", STEPS=1)])]),
    )  # fmt: skip
    cat.script(block("event_whenkeypressed", KEY_OPTION="left arrow"), block("motion_movesteps", STEPS=-5))
    cat.script(block("event_whenkeypressed", KEY_OPTION="any"), block("motion_movesteps", STEPS=1))
    cat.script(block("event_whenthisspriteclicked"), block("looks_hide"))
    cat.script(block("event_whenbroadcastreceived", BROADCAST_OPTION="go"), block("looks_show"))
    return project.to_project_json()


def test_the_plan_does_what_the_hats_listen_to_after_the_flag_in_time() -> None:
    inputs = program_inputs(listening())
    assert inputs.keys == ["a", "left arrow", "space"]  # `key pressed?` too; `any` as the space key
    assert (inputs.clicks, inputs.stage_click, inputs.backdrops, inputs.messages) == (["Cat"], True, ["night"], ["go"])
    assert not inputs.asks
    plan = exploration_plan(listening(), "Move the cat.")
    assert [e.name for e in plan.episodes] == [f"seed {s}" for s in SEEDS] and {e.seed for e in plan.episodes} == {
        1,
        2,
        3,
    }
    stimuli = plan.episodes[0].stimuli
    assert stimuli[0] == Stimulus(at_ms=0, kind="green_flag")
    assert [(s.kind, s.name) for s in stimuli[1:]] == [
        ("key", "a"), ("key", "left arrow"), ("key", "space"), ("click", "Cat"), ("stage_click", ""),
        ("backdrop", "night"), ("broadcast", "go"),
    ]  # fmt: skip
    times = [s.at_ms for s in stimuli]
    assert times == sorted(times) and times[1] >= 1000 and plan.episodes[0].span_ms >= times[-1] + 2000
    assert all(s.hold_ms > 0 for s in stimuli if s.kind == "key")
    assert exploration_plan(listening(), "Move the cat.") == plan  # the same inputs, the same plan


def test_a_program_that_asks_gets_the_tasks_answers_generic_ones_and_none_each_with_its_seed() -> None:
    instruction = 'Ask for two numbers and say their sum (answering 3 and 4 says 7; "hello" is no number).'
    assert instruction_answers(instruction) == (["3", "4", "7"], ["hello"])
    plan = exploration_plan(listening(asks=True), instruction)
    answers = {e.name.split("answers: ")[1]: e.answers for e in plan.episodes}
    assert answers["task numbers"] == ["3", "4", "7"] and answers["task numbers reversed"] == ["7", "4", "3"]
    assert answers["task words"] == ["hello"] and answers["empty"] == [""]
    assert "generic numbers" in answers and "generic words" in answers
    assert len({e.seed for e in plan.episodes}) == len(plan.episodes)  # several seeds
    assert plan.answer_domain == "numbers" and "asks" not in plan.domain_source  # 'Ask for two numbers'
    assert "Ask for two numbers" in plan.domain_source


def test_the_answer_domain_is_the_declaration_else_the_instructions_words_else_any() -> None:
    assert answer_domain_from("the sprite asks for a word and says it backwards") == (
        "words",
        "asks for a word and says it backwards",
    )
    assert answer_domain_from("it asks for a whole number")[0] == "integers"  # type: ignore[index]
    assert answer_domain_from("it asks for a base number, then asks for an exponent (a whole number)")[0] == "numbers"  # type: ignore[index]
    assert answer_domain_from('it asks "What is 7 + 5?" and says "Correct!"') is None  # no kind of answer named
    assert answer_domain_from("it asks for a number, then asks for a word") is None  # two kinds: any
    project = listening(asks=True)
    said = exploration_plan(project, "It asks for a number.")
    declared = exploration_plan(project, "It asks for a number.", "text", "tasks/x/audit.yaml")
    unsaid = exploration_plan(project, "It asks something.")
    assert (said.answer_domain, declared.answer_domain, unsaid.answer_domain) == ("numbers", "text", "any")
    assert declared.domain_source == "declared in tasks/x/audit.yaml"


def test_the_plan_is_part_of_every_job_id_of_its_task(tmp_path: Path) -> None:
    content = read_task(load_suite(SUITE_DIR).task("sum_two_numbers"))
    settings = AuditSweep(mutants_per_task=3, refactorings_per_task=1)

    def ids(declared: TaskDeclarations | None) -> list[str]:
        found = {"sum_two_numbers": declared} if declared else {}
        return [job.job_id for job in audit_jobs([content], settings, DEFAULT_AGENT, "h", None, found)]

    plain, again = ids(None), ids(None)
    words = ids(TaskDeclarations(answers="words"))
    numbers = ids(TaskDeclarations(answers="numbers", source="elsewhere/audit.yaml"))
    assert plain == again and len(plain) == 5
    assert not set(words) & set(plain)  # another answer domain: every job is another
    assert numbers == plain  # what the instruction says already: the same plan (where it is said is no part of it)
    assert ids(TaskDeclarations(explained=[])) == plain  # explained holes are the report's: the jobs stay
    limited = audit_jobs([content], settings, DEFAULT_AGENT, "h", ProjectLimits(max_json_mb=1), {})
    assert not {job.job_id for job in limited} & set(plain)  # a project over the limits is refused: other jobs
