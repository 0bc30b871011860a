"""A test-only suite for the flake finder: one evaluation script that depends on the frame phase, one that does not.

``phase_sensitive`` judges a frame counter 50 ms after the green flag: two frames fit in 50 ms
when the first one comes within 17 ms of the script's start, one frame otherwise, so its verdict
depends on the phase at which the script meets the VM's frame loop (and on timer lateness, which
stretches the frame interval). ``steady`` judges a counter that stops after three frames, a second
later, and a random draw by its range: no perturbation changes either.
"""

from __future__ import annotations

import json
from pathlib import Path

from scratchworld_dist.sb3 import Project, block, rect_costume
from tests.conftest import SUITE_DIR

PHASE_SENSITIVE_JS = """
module.exports = async (vm) => Harness.runTests(vm, [{
  name: 'two frames within 50 ms of the green flag',
  timeoutMs: 5000,
  run: async () => {
    vm.greenFlag();
    await Harness.wait(50);
    const ticks = Harness.valueOf(vm, 'ticks');
    return {passed: ticks === 2, meta: {ticks}};
  },
}]);
"""

STEADY_JS = """
module.exports = async (vm) => Harness.runTests(vm, [
  {
    name: 'three ticks, a second later',
    timeoutMs: 5000,
    run: async () => {
      await Harness.start(vm);
      await Harness.wait(1000);
      return {passed: Harness.valueOf(vm, 'ticks') === 3};
    },
  },
  {
    name: 'a draw from 1 to 10',
    timeoutMs: 5000,
    run: async () => {
      const drawn = Harness.valueOf(vm, 'drawn');
      return {passed: drawn >= 1 && drawn <= 10, meta: {drawn}};
    },
  },
]);
"""


def _counter(loop: object | None, *, draw: bool = False) -> bytes:
    project = Project()
    project.stage.variable("ticks", 0)
    project.stage.variable("drawn", 0)
    script = [
        block("event_whenflagclicked"),
        block("motion_setx", X=-200),
        block("data_setvariableto", VARIABLE="ticks", VALUE=0),
    ]
    if draw:
        script.append(block("data_setvariableto", VARIABLE="drawn", VALUE=block("operator_random", FROM=1, TO=10)))
    if loop is not None:
        script.append(loop)  # type: ignore[arg-type]
    project.sprite("Mover", costume=rect_costume("box", 20, 20, "#3366ff"), x=-200).script(*script)
    return project.to_sb3()


def _tick() -> list[object]:
    """One tick per frame: the move asks for a redraw, which ends the VM's frame (else a loop runs on all frame)."""
    return [block("data_changevariableby", VARIABLE="ticks", VALUE=1), block("motion_changexby", DX=1)]


def _task(suite: Path, task_id: str, script: str, golden: bytes, initial: bytes) -> None:
    folder = suite / "create" / task_id
    folder.mkdir(parents=True)
    (folder / "task.json").write_text(json.dumps({"instruction": f"Build {task_id}.", "timeout_s": 20}))
    (folder / "evaluate.js").write_text(script)
    (folder / "golden.sb3").write_bytes(golden)
    (folder / "initial.sb3").write_bytes(initial)


def write_flaky_suite(suite: Path) -> Path:
    """The two tasks in ``suite`` (a new folder), with our suite's helper."""
    suite.mkdir(parents=True)
    for name in ("suite.json", "harness.js"):
        (suite / name).write_bytes((SUITE_DIR / name).read_bytes())
    forever = block("control_forever", SUBSTACK=_tick())
    _task(suite, "phase_sensitive", PHASE_SENSITIVE_JS, _counter(forever), _counter(None))
    three = block("control_repeat", TIMES=3, SUBSTACK=_tick())
    _task(suite, "steady", STEADY_JS, _counter(three, draw=True), _counter(None))
    return suite
