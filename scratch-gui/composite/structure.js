/*
 * Moves on the VM's own block container (what every connect, detach and delete is made of):
 * find a chain's end and where a block hangs, take a block out (healing the gap or not), hang it
 * elsewhere, let it take another's place, and count what a deletion removes.
 */
scratchworldModule({name: 'composite/structure', requires: ['composite/numbering'], create(ctx, numbering) {
  'use strict';

  function chainEnd(blocks, id) {
    let block = blocks.getBlock(id);
    while (block.next) block = blocks.getBlock(block.next);
    return block;
  }

  // Where a block hangs: {parent, input} (input null: the parent's next), or null when top-level.
  function attachment(blocks, block) {
    if (!block.parent) return null;
    const parent = blocks.getBlock(block.parent);
    if (parent.next === block.id) return {parent: parent.id, input: null};
    for (const name of Object.keys(parent.inputs)) if (parent.inputs[name].block === block.id) return {parent: parent.id, input: name};
    return null;
  }

  function containsBlock(blocks, rootId, wanted) {
    const stack = [rootId];
    while (stack.length) {
      const id = stack.pop();
      if (id === wanted) return true;
      const block = blocks.getBlock(id);
      if (!block) continue;
      if (block.next) stack.push(block.next);
      for (const input of Object.values(block.inputs)) if (input.block) stack.push(input.block);
    }
    return false;
  }

  function bottomY(blocks) {
    let y = 0;
    for (const top of numbering.topBlocks(blocks)) y = Math.max(y, Number(top.y) || 0);
    return y;
  }

  // Make `id` top-level. With heal, only the block leaves: its next takes its place.
  function unplug(blocks, id, heal) {
    const block = blocks.getBlock(id);
    const at = attachment(blocks, block);
    const next = heal ? block.next : null;
    if (next) blocks.moveBlock({id: next, oldParent: id, newCoordinate: {x: 0, y: 0}});
    if (at) {
      blocks.moveBlock({id: id, oldParent: at.parent, oldInput: at.input || undefined, newCoordinate: {x: 400, y: bottomY(blocks) + 120}});
      if (at.input) restoreShadow(blocks, at.parent, at.input);
    } else if (!block.topLevel) {
      blocks.moveBlock({id: id, newCoordinate: {x: 400, y: bottomY(blocks) + 120}});
    }
    if (next) {
      if (at) attach(blocks, next, at.parent, at.input);
      else blocks.moveBlock({id: next, newCoordinate: {x: Number(block.x) || 0, y: Number(block.y) || 0}});
    }
  }

  function restoreShadow(blocks, parentId, inputName) {
    const input = blocks.getBlock(parentId).inputs[inputName];
    if (input && !input.block && input.shadow) input.block = input.shadow;
  }

  // Hang a top-level block under parent (input null: as its next).
  function attach(blocks, id, parentId, inputName) {
    blocks.moveBlock({id: id, newParent: parentId, newInput: inputName || undefined});
  }

  // The (top-level) source takes the destination's place; the destination is left top-level.
  function takePlace(blocks, sourceId, destId) {
    const dest = blocks.getBlock(destId);
    const at = attachment(blocks, dest);
    if (at) {
      blocks.moveBlock({id: destId, oldParent: at.parent, oldInput: at.input || undefined, newCoordinate: {x: 0, y: 0}});
      attach(blocks, sourceId, at.parent, at.input);
    } else {
      placeTop(blocks, sourceId, Number(dest.x) || 0, Number(dest.y) || 0);
    }
  }

  function placeTop(blocks, id, x, y) {
    blocks.moveBlock({id: id, newCoordinate: {x: x, y: y}});
  }

  function countTree(blocks, id) {
    const block = blocks.getBlock(id);
    let n = block.shadow ? 0 : 1;
    for (const input of Object.values(block.inputs)) {
      if (input.block && input.block !== input.shadow) n += countChain(blocks, input.block);
    }
    return n;
  }

  function countChain(blocks, id) {
    let n = 0;
    for (let cursor = id; cursor; cursor = blocks.getBlock(cursor).next) n += countTree(blocks, cursor);
    return n;
  }

  return {
    chainEnd: chainEnd, attachment: attachment, containsBlock: containsBlock, bottomY: bottomY, unplug: unplug,
    attach: attach, takePlace: takePlace, placeTop: placeTop, countTree: countTree,
  };
}});
