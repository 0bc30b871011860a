"""A fake upstream clone, written by us: three tasks in upstream's format, for tests of the layout alone.

Tests of how a clone is read (loaders, task lists, missing files, defaults an upstream suite gets) need
its layout, not upstream's content, so they run on this and never skip; tests of upstream's real tasks
read ``../shared`` (the ``upstream_dir`` fixture, marked ``upstream``). The layout, as
``scratchworld_dist/suites/_upstream.py`` reads it::

    tasks/<category>/<name>.json, tasks/<list>.json
    scratch-gui/static/<initial_project>, <name>_golden.sb3 (a debug task: its starter's golden)
    scratch-bench-api/api/evaluation_scripts/<name>.js, evaluation_utils.js
"""

from __future__ import annotations

import json
import shutil
from pathlib import Path

from scratchworld_dist.sb3 import Project, block, circle_costume
from tests.conftest import DATA, SUITE_DIR

TASKS = {"create": ["say_hello"], "compute": ["sum_two"], "debug": ["sum_two_says_nothing_error"]}
"""The clone's tasks by category (``sorted`` order is the suite's)."""

SUM_TWO_JS = """// Test script for the fake clone's sum_two task (written here), in the calculate_gcd script's style.
module.exports = async (vm) => {
  const cases = [[[3, 4], 7], [[12, 30], 42]];
  const details = [];
  for (const [inputs, expected] of cases) {
    const replies = await EvaluationUtils.collectReplies(vm, 'Calculator', inputs, 4000);
    details.push({name: `${inputs.join(' + ')} = ${expected}`, passed: Number(replies[0]) === expected});
  }
  return {details};
};
"""


def _sprite1(*script: dict) -> bytes:
    project = Project()
    sprite = project.sprite("Sprite1", costume=circle_costume("dot", 10, "#36c"))
    if script:
        sprite.script(*script)
    return project.to_sb3()


def fake_clone(root: Path) -> Path:
    """Write the clone at ``root`` (created) and return it."""
    static = root / "scratch-gui" / "static"
    scripts = root / "scratch-bench-api" / "api" / "evaluation_scripts"
    static.mkdir(parents=True)
    scripts.mkdir(parents=True)
    shutil.copy(DATA / "upstream_scripts" / "evaluation_utils.js", scripts)

    (static / "default.sb3").write_bytes(_sprite1())
    (static / "say_hello_golden.sb3").write_bytes(
        _sprite1(block("event_whenflagclicked"), block("looks_say", MESSAGE="hello"))
    )
    shutil.copy(DATA / "upstream_scripts" / "say_hello.js", scripts / "say_hello.js")
    sum_two = SUITE_DIR / "compute" / "sum_two_numbers"
    shutil.copy(sum_two / "initial.sb3", static / "sum_two.sb3")
    shutil.copy(sum_two / "golden.sb3", static / "sum_two_golden.sb3")  # the debug task's golden too
    (scripts / "sum_two.js").write_text(SUM_TWO_JS)
    (scripts / "sum_two_says_nothing_error.js").write_text(SUM_TWO_JS)

    initial = {"say_hello": "default.sb3", "sum_two": "sum_two.sb3", "sum_two_says_nothing_error": "sum_two.sb3"}
    for category, names in TASKS.items():
        (root / "tasks" / category).mkdir(parents=True)
        for name in names:
            task = {
                "name": name,
                "type": category,
                "instruction": f"The fake clone's {name} task.",
                "initial_project": initial[name],
                "evaluation": {"function": name, "timeout": 20},
            }
            (root / "tasks" / category / f"{name}.json").write_text(json.dumps(task, indent=2))
    lists = {
        "2_tasks": {"create": ["say_hello.json"], "compute": ["sum_two.json"]},
        "all_tasks": {category: [f"{name}.json" for name in names] for category, names in TASKS.items()},
    }
    for name, listing in lists.items():
        (root / "tasks" / f"{name}.json").write_text(json.dumps(listing, indent=2))
    return root
