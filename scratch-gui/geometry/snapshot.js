/*
 * The project's meaning without ids or positions: per target its variables, lists and scripts as
 * sorted trees (two ways of building the same scripts compare equal), and every block's
 * structural path, stable across loads of a project. Read-only.
 */
scratchworldModule({name: 'geometry/snapshot', requires: ['blockly'], create(ctx, blockly) {
  'use strict';

  /* ---------- semantic snapshot ---------- */

  function chainOf(blocks, id) {
    const chain = [];
    for (let cursor = id; cursor;) {
      const block = blocks.getBlock(cursor);
      if (!block) break;
      const fields = {};
      for (const name of Object.keys(block.fields).sort()) fields[name] = String(block.fields[name].value);
      const inputs = {};
      for (const name of Object.keys(block.inputs).sort()) {
        const input = block.inputs[name];
        if (input.block) inputs[name] = chainOf(blocks, input.block);
      }
      chain.push({opcode: block.opcode, shadow: !!block.shadow, fields: fields, inputs: inputs});
      cursor = block.next;
    }
    return chain;
  }

  // Per target: its variables and lists (names), and its scripts as id- and position-free
  // trees, sorted, so two projects built differently compare equal when they mean the same.
  function snapshot() {
    const vm = ctx.requireVm();
    const targets = vm.runtime.targets.filter((t) => t.isOriginal).map((target) => {
      const variables = Object.values(target.variables)
        .filter((v) => v.type === '' || v.type === 'list')
        .map((v) => `${v.type || 'variable'}:${v.name}`)
        .sort();
      const scripts = target.blocks.getScripts()
        .map((id) => target.blocks.getBlock(id))
        .filter((b) => b && !b.shadow)
        .map((b) => JSON.stringify(chainOf(target.blocks, b.id)))
        .sort();
      return {name: target.getName(), isStage: target.isStage, variables: variables, scripts: scripts};
    });
    return {editingTarget: vm.editingTarget ? vm.editingTarget.getName() : null, targets: targets};
  }

  // Every non-shadow block of every target by a structural path ("Target/script/position/INPUT/...",
  // scripts ordered by position then content): ids of compact blocks (variable reporters) are new
  // on every load of a project, paths are not.
  function blockPaths() {
    const vm = ctx.requireVm();
    const paths = {};
    for (const target of vm.runtime.targets.filter((t) => t.isOriginal)) {
      const blocks = target.blocks;
      const own = paths[target.getName()] = {};
      const visit = (id, path) => {
        let n = 0;
        for (let cursor = id; cursor; n++) {
          const block = blocks.getBlock(cursor);
          if (!block) break;
          const here = `${path}/${n}`;
          if (!block.shadow) own[block.id] = here;
          for (const name of Object.keys(block.inputs).sort()) {
            const input = block.inputs[name];
            if (input.block) visit(input.block, `${here}/${name}`);
          }
          cursor = block.next;
        }
      };
      blocks.getScripts().map((id) => blocks.getBlock(id)).filter((b) => b && !b.shadow)
        .map((b) => ({id: b.id, x: Number(b.x) || 0, y: Number(b.y) || 0, key: JSON.stringify(chainOf(blocks, b.id))}))
        .sort((a, b) => a.y - b.y || a.x - b.x || (a.key < b.key ? -1 : a.key > b.key ? 1 : 0))
        .forEach((top, k) => visit(top.id, `${target.getName()}/${k}`));
    }
    return {paths: paths};
  }

  return {
    snapshot: snapshot,
    api: {
      geometryTopBlocks: () => blockly.topBlocks(),
      geometryBlockPaths: () => blockPaths(),
      geometrySnapshot: () => {
        const state = snapshot();
        return {state: state, text: JSON.stringify(state)};
      },
    },
  };
}});
