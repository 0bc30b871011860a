/*
 * What the oracle planner reads of a loaded project: every original target's blocks exactly as the
 * VM holds them (id, opcode, fields, inputs with their block and shadow, next, parent, a script's
 * position), its
 * variables, lists and messages, its costumes and sounds, and the state a sprite is saved with;
 * plus the composite numbering of the editing target (the block id behind each #n), so a plan made
 * of block ids can be written as the index-based calls an agent sends. Read-only.
 */
scratchworldModule({name: 'oracle/project-state', requires: ['composite/target', 'composite/numbering'], create(ctx, editing, numbering) {
  'use strict';

  const MAX_BLOCKS = 20000;

  function plain(value) {
    return value === undefined ? null : JSON.parse(JSON.stringify(value));
  }

  function blockState(block) {
    const fields = {};
    for (const [name, field] of Object.entries(block.fields || {})) {
      fields[name] = {value: field.value === undefined || field.value === null ? '' : String(field.value), id: field.id || null};
    }
    const inputs = {};
    for (const [name, input] of Object.entries(block.inputs || {})) {
      inputs[name] = {block: input.block || null, shadow: input.shadow || null};
    }
    return {
      id: block.id, opcode: block.opcode, shadow: !!block.shadow, topLevel: !!block.topLevel,
      parent: block.parent || null, next: block.next || null, fields: fields, inputs: inputs,
      x: typeof block.x === 'number' ? block.x : null, y: typeof block.y === 'number' ? block.y : null,
      mutation: block.mutation ? plain(block.mutation) : null
    };
  }

  function targetState(target, budget) {
    const blocks = {};
    for (const [id, block] of Object.entries(target.blocks._blocks)) {
      if (budget.left-- <= 0) throw new ctx.BridgeFailure('too_large', `the project has over ${MAX_BLOCKS} blocks`);
      blocks[id] = blockState(block);
    }
    const sprite = target.sprite;
    return {
      name: target.getName(), isStage: !!target.isStage,
      variables: Object.values(target.variables).map((v) => ({id: v.id, name: v.name, type: v.type || ''})),
      costumes: sprite.costumes.map((c) => ({name: c.name, assetId: c.assetId || null})),
      sounds: sprite.sounds.map((s) => ({name: s.name, assetId: s.assetId || null})),
      x: target.x, y: target.y, direction: target.direction, size: target.size, visible: !!target.visible,
      currentCostume: target.currentCostume, rotationStyle: target.rotationStyle || null,
      blocks: blocks
    };
  }

  function projectState() {
    const vm = editing.vm();
    const budget = {left: MAX_BLOCKS};
    const editingTarget = vm.editingTarget ? vm.editingTarget.getName() : null;
    return {editingTarget: editingTarget, targets: vm.runtime.targets.filter((t) => t.isOriginal).map((t) => targetState(t, budget))};
  }

  function blockIndexes() {
    const target = editing.target();
    return {editingTarget: target.getName(), ids: numbering.indexMap(target).slice(1)};
  }

  return {api: {oracleProjectState: () => projectState(), oracleBlockIndexes: () => blockIndexes()}};
}});
