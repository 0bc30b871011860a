/*
 * One deterministic pre-order of the editing target's blocks, shared by the observation (#n in
 * the pseudocode) and the actions (block indexes): scripts by position, then each block, its
 * value inputs, its statement inputs and its next block.
 */
scratchworldModule({name: 'composite/numbering', requires: ['composite/catalog'], create(ctx, catalog) {
  'use strict';

  const STATEMENT_INPUTS = ['SUBSTACK', 'SUBSTACK2'];

  function topBlocks(blocks) {
    return blocks.getScripts().slice().map((id) => blocks.getBlock(id)).filter((b) => b && !b.shadow)
      .sort((a, b) => (Number(a.y) || 0) - (Number(b.y) || 0) || (Number(a.x) || 0) - (Number(b.x) || 0) || (a.id < b.id ? -1 : 1));
  }

  function orderedInputs(block) {
    const shape = catalog.shapeOf(block.opcode);
    // Every input of the definition is listed, filled or not (an empty CONDITION is worth seeing).
    const names = shape ? shape.inputs.map((i) => i.name) : [];
    for (const name of Object.keys(block.inputs)) if (names.indexOf(name) === -1) names.push(name);
    const value = names.filter((n) => STATEMENT_INPUTS.indexOf(n) === -1 && !(shape && shape.inputs.some((i) => i.name === n && i.kind === 'statement')));
    const statement = names.filter((n) => value.indexOf(n) === -1);
    return {value, statement};
  }

  // Walks the editing target; calls visit(block, depth, index, context) for every indexed block.
  function walk(blocks, visit) {
    let counter = 0;
    function visitChain(id, depth, topLevel) {
      let first = true;
      while (id) {
        const block = blocks.getBlock(id);
        if (!block) return;
        counter += 1;
        visit(block, depth, counter, topLevel && first);
        const {value, statement} = orderedInputs(block);
        for (const name of value) {
          const input = block.inputs[name];
          if (input && input.block && input.block !== input.shadow) {
            visit.input && visit.input(block, name, depth);
            visitChain(input.block, depth + 1, false);
          } else {
            visit.literal && visit.literal(block, name, depth);
          }
        }
        for (const name of statement) {
          const input = block.inputs[name];
          visit.statement && visit.statement(block, name, depth, !!(input && input.block));
          if (input && input.block) visitChain(input.block, depth + 1, false);
        }
        first = false;
        id = block.next;
      }
    }
    const tops = topBlocks(blocks);
    tops.forEach((block, n) => {
      visitChain(block.id, 0, true);
      visit.endScript && visit.endScript(n);
    });
    return counter;
  }

  function indexMap(target) {
    const byIndex = [null];
    walk(target.blocks, (block) => { byIndex.push(block.id); });
    return byIndex;
  }

  return {topBlocks: topBlocks, walk: walk, indexMap: indexMap};
}});
