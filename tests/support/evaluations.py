"""Evaluations as tests run them: a spec around a script's source, a project evaluated with it, and a pair of
scripts for isolation checks (``LEAKY`` changes all it can in the page, ``CHECK_CLEAN`` fails on any of it)."""

from __future__ import annotations

from scratchworld_dist.sb3 import Project
from tests.support.projects import counter_project
from workers.contract import EvalResult, EvaluationSpec
from workers.evaluation import Evaluator


def spec(source: str, timeout_s: float = 10, **extra: object) -> EvaluationSpec:
    return EvaluationSpec(script_name="test.js", script_source=source, timeout_s=timeout_s, **extra)  # type: ignore[arg-type]


async def evaluate(evaluator: Evaluator, source: str, project: Project | bytes | None = None, **extra) -> EvalResult:
    data = project if isinstance(project, bytes) else (project or counter_project()).to_sb3()
    return await evaluator.evaluate(data, spec(source, **extra))


LEAKY = """
module.exports = async (vm) => {
  window.leakedGlobal = 'from the first project';
  localStorage.setItem('leaked', 'yes');
  vm.runtime.getTargetForStage().lookupVariableByNameAndType('count', '').value = 999;
  vm.postIOData('mouse', {x: 400, y: 50, canvasWidth: 480, canvasHeight: 360, isDown: true});
  vm.runtime.on('SAY', () => { window.leakedSays = (window.leakedSays || 0) + 1; });
  vm.greenFlag();  // leaves threads running
  return {details: [{name: 'mutated', passed: true}]};
};
"""

CHECK_CLEAN = """
module.exports = async (vm) => {
  const count = vm.runtime.getTargetForStage().lookupVariableByNameAndType('count', '');
  const mouse = vm.runtime.ioDevices.mouse;
  return {details: [
    {name: 'no global from before', passed: typeof window.leakedGlobal === 'undefined'},
    {name: 'no storage from before', passed: localStorage.getItem('leaked') === null},
    {name: 'variable as saved in this project', passed: count.value === 0, meta: {value: count.value}},
    {name: 'mouse never moved', passed: !mouse.getIsDown() && mouse.getClientX() === undefined,
     meta: {x: mouse.getClientX() === undefined ? null : mouse.getClientX()}},
    {name: 'no threads running', passed: vm.runtime.threads.length === 0},
    {name: 'only this project', passed: vm.runtime.targets.map(t => t.getName()).join() === 'Stage,Counter'},
  ]};
};
"""
