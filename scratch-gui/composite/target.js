/*
 * The VM as composite actions see it: the target being edited, the stage, the variables, lists
 * and messages in a target's scope, and ids for new blocks and variables (numbered per project,
 * so a reused page names the next project's blocks as a fresh page would).
 */
scratchworldModule({name: 'composite/target', requires: ['composite/arguments'], create(ctx, checks) {
  'use strict';

  let uid = 0;
  ctx.onProjectLoaded(() => { uid = 0; });

  function vm() {
    return ctx.requireVm();
  }

  function target() {
    const edited = vm().editingTarget;
    if (!edited) throw new checks.ActionError('NO_TARGET', 'no target is being edited');
    return edited;
  }

  function stage() {
    return vm().runtime.getTargetForStage();
  }

  function variablesInScope(target, type) {
    const found = new Map();
    for (const owner of [stage(), target]) {
      if (!owner) continue;
      for (const variable of Object.values(owner.variables)) {
        if (variable.type === type) found.set(variable.name, {variable: variable, scope: owner.isStage ? 'all' : 'sprite'});
      }
    }
    return [...found.values()].sort((a, b) => (a.variable.name < b.variable.name ? -1 : a.variable.name > b.variable.name ? 1 : 0));
  }

  function newId(prefix) {
    uid += 1;
    return `${prefix || 'sw'}${Date.now().toString(36)}${uid.toString(36)}`;
  }

  function changed() {
    const theVm = vm();
    theVm.runtime.emitProjectChanged();
    if (theVm.editingTarget) theVm.editingTarget.blocks.resetCache();
  }

  return {vm: vm, target: target, stage: stage, variablesInScope: variablesInScope, newId: newId, changed: changed};
}});
