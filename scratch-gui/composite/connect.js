/*
 * `connect_blocks`: a block goes before, after, into a C-slot or an input of another, or wraps it,
 * as the editor would connect them by hand; what the move displaces is rechained or set apart,
 * and every impossible placement is a CONNECTION_MISMATCH or INPUT_NOT_FOUND answer.
 */
scratchworldModule({name: 'composite/connect', requires: ['composite/arguments', 'composite/target', 'composite/catalog', 'composite/numbering', 'composite/structure'], create(ctx, checks, editing, catalog, numbering, structure) {
  'use strict';

  const PLACEMENTS = ['stack_before', 'stack_after', 'statement_into', 'value_into', 'wrap'];

  function connectBlocks(args) {
    const target = editing.target();
    const blocks = target.blocks;
    const byIndex = numbering.indexMap(target);
    const sourceId = checks.requireIndex(args, 'sourceBlockIndex', byIndex);
    const targetId = checks.requireIndex(args, 'targetBlockIndex', byIndex);
    if (sourceId === targetId) throw new checks.ActionError('INVALID_ARG', 'a block cannot connect to itself');
    const placement = args.placement;
    if (typeof placement !== 'object' || placement === null || PLACEMENTS.indexOf(placement.kind) === -1) {
      throw new checks.ActionError('INVALID_ARG', `placement.kind must be one of ${PLACEMENTS.join(', ')}`);
    }
    const source = blocks.getBlock(sourceId);
    const dest = blocks.getBlock(targetId);
    const sourceShape = catalog.shapeOf(source.opcode);
    const destShape = catalog.shapeOf(dest.opcode);
    if (!sourceShape || !destShape) throw new checks.ActionError('UNSUPPORTED', 'blocks outside the catalog cannot be connected');
    const kind = placement.kind;
    // A hat moves with its whole script; any other block moves alone (with its inputs and C-slots).
    const movesStack = sourceShape.hat;
    if (structure.containsBlock(blocks, sourceId, targetId) && (movesStack || !isInChainOf(blocks, sourceId, targetId))) {
      throw new checks.ActionError('INVALID_ARG', `block #${args.targetBlockIndex} is inside block #${args.sourceBlockIndex}: that would make a cycle`);
    }
    const inputName = placement.inputName;
    if (kind === 'value_into') return valueInto(blocks, source, sourceShape, dest, destShape, inputName, args);
    if (sourceShape.reporter) {
      throw new checks.ActionError('CONNECTION_MISMATCH', `block #${args.sourceBlockIndex} (${source.opcode}) is a reporter: use placement value_into an input`);
    }
    if (kind === 'stack_before') return stackBefore(blocks, source, sourceShape, dest, destShape, args);
    if (kind === 'stack_after') return stackAfter(blocks, source, sourceShape, dest, destShape, args);
    if (kind === 'statement_into') return statementInto(blocks, source, sourceShape, dest, destShape, inputName, args);
    return wrap(blocks, source, sourceShape, dest, destShape, args);
  }

  function isInChainOf(blocks, sourceId, targetId) {
    // true when target is only reachable through source's next chain (it moves away when source is healed out)
    const source = blocks.getBlock(sourceId);
    for (const input of Object.values(source.inputs)) if (input.block && structure.containsBlock(blocks, input.block, targetId)) return false;
    return true;
  }

  function result(source, extra) {
    editing.changed();
    const data = {connected: true, sourceBlockId: source.id};
    return Object.assign(data, extra || {});
  }

  function stackBefore(blocks, source, sourceShape, dest, destShape, args) {
    if (!destShape.previous) {
      throw new checks.ActionError('CONNECTION_MISMATCH', `nothing can go before block #${args.targetBlockIndex} (${dest.opcode}): it is a hat block`);
    }
    if (sourceShape.hat && structure.attachment(blocks, dest)) {
      throw new checks.ActionError('CONNECTION_MISMATCH', `a hat block can only go on top of a script; block #${args.targetBlockIndex} is not the first block of one`);
    }
    const tail = sourceShape.hat ? structure.chainEnd(blocks, source.id) : source;
    const tailShape = catalog.shapeOf(tail.opcode);
    if (!tailShape || !tailShape.next) {
      throw new checks.ActionError('CONNECTION_MISMATCH', `nothing can follow ${tail.opcode}, so it cannot go before another block`);
    }
    structure.unplug(blocks, source.id, !sourceShape.hat);
    structure.takePlace(blocks, source.id, dest.id);
    structure.attach(blocks, dest.id, tail.id, null);
    return result(source);
  }

  function stackAfter(blocks, source, sourceShape, dest, destShape, args) {
    if (sourceShape.hat) throw new checks.ActionError('CONNECTION_MISMATCH', `block #${args.sourceBlockIndex} is a hat block: it can only start a script (stack_before its first block)`);
    if (!destShape.next) throw new checks.ActionError('CONNECTION_MISMATCH', `nothing can follow block #${args.targetBlockIndex} (${dest.opcode})`);
    structure.unplug(blocks, source.id, true);
    const oldNext = blocks.getBlock(dest.id).next;
    let detached = null;
    if (oldNext) blocks.moveBlock({id: oldNext, oldParent: dest.id, newCoordinate: {x: 0, y: 0}});
    structure.attach(blocks, source.id, dest.id, null);
    if (oldNext) detached = rechain(blocks, source.id, oldNext);
    return result(source, detached ? {detachedBlockId: detached} : null);
  }

  // Hang `tailId` (top-level) after the chain starting at `headId`; if the chain ends in a cap, it stays apart.
  function rechain(blocks, headId, tailId) {
    const end = structure.chainEnd(blocks, headId);
    if (catalog.shapeOf(end.opcode) && catalog.shapeOf(end.opcode).next) {
      structure.attach(blocks, tailId, end.id, null);
      return null;
    }
    structure.placeTop(blocks, tailId, 400, structure.bottomY(blocks) + 120);
    return tailId;
  }

  function statementInputs(shape) {
    return shape.inputs.filter((i) => i.kind === 'statement').map((i) => i.name);
  }

  function valueInputs(shape) {
    return shape.inputs.filter((i) => i.kind === 'value').map((i) => i.name);
  }

  function statementInto(blocks, source, sourceShape, dest, destShape, inputName, args) {
    const names = statementInputs(destShape);
    if (typeof inputName !== 'string' || names.indexOf(inputName) === -1) {
      throw new checks.ActionError('INPUT_NOT_FOUND', names.length
        ? `block #${args.targetBlockIndex} (${dest.opcode}) has statement inputs ${names.join(', ')}; give one as placement.inputName`
        : `block #${args.targetBlockIndex} (${dest.opcode}) has no statement input (it is not a C block)`, {statementInputs: names});
    }
    if (sourceShape.hat) throw new checks.ActionError('CONNECTION_MISMATCH', `block #${args.sourceBlockIndex} is a hat block and cannot go inside a C block`);
    structure.unplug(blocks, source.id, true);
    const input = blocks.getBlock(dest.id).inputs[inputName];
    const old = input && input.block ? input.block : null;
    if (old) blocks.moveBlock({id: old, oldParent: dest.id, oldInput: inputName, newCoordinate: {x: 0, y: 0}});
    structure.attach(blocks, source.id, dest.id, inputName);
    const detached = old ? rechain(blocks, source.id, old) : null;
    return result(source, detached ? {detachedBlockId: detached} : null);
  }

  function valueInto(blocks, source, sourceShape, dest, destShape, inputName, args) {
    const names = valueInputs(destShape);
    if (typeof inputName !== 'string' || names.indexOf(inputName) === -1) {
      throw new checks.ActionError('INPUT_NOT_FOUND', names.length
        ? `block #${args.targetBlockIndex} (${dest.opcode}) has inputs ${names.join(', ')}; give one as placement.inputName`
        : `block #${args.targetBlockIndex} (${dest.opcode}) has no inputs`, {inputs: names});
    }
    if (!sourceShape.reporter) {
      throw new checks.ActionError('CONNECTION_MISMATCH', `block #${args.sourceBlockIndex} (${source.opcode}) is not a reporter; only reporters and booleans go into inputs`);
    }
    const spec = destShape.inputs.find((i) => i.name === inputName);
    if (spec.boolean && !sourceShape.boolean) {
      throw new checks.ActionError('CONNECTION_MISMATCH', `input ${inputName} of block #${args.targetBlockIndex} takes a boolean (hexagonal) block; ${source.opcode} is a round reporter`);
    }
    structure.unplug(blocks, source.id, false);
    const input = blocks.getBlock(dest.id).inputs[inputName];
    let unplugged = null;
    if (input && input.block && input.block !== input.shadow) {
      unplugged = input.block;
      structure.unplug(blocks, unplugged, false);
    }
    structure.attach(blocks, source.id, dest.id, inputName);
    return result(source, unplugged ? {detachedBlockId: unplugged} : null);
  }

  function wrap(blocks, source, sourceShape, dest, destShape, args) {
    const slots = statementInputs(sourceShape);
    if (slots.indexOf('SUBSTACK') === -1 || !sourceShape.previous) {
      throw new checks.ActionError('CONNECTION_MISMATCH', `block #${args.sourceBlockIndex} (${source.opcode}) is not a C block and cannot wrap`);
    }
    if (source.inputs.SUBSTACK && source.inputs.SUBSTACK.block) {
      throw new checks.ActionError('INVALID_ARG', `block #${args.sourceBlockIndex} already holds blocks in SUBSTACK; wrap needs an empty C block`);
    }
    if (!destShape.previous) {
      throw new checks.ActionError('CONNECTION_MISMATCH', `block #${args.targetBlockIndex} is a hat block; wrap the block under it instead`);
    }
    structure.unplug(blocks, source.id, true);
    structure.takePlace(blocks, source.id, dest.id);
    structure.attach(blocks, dest.id, source.id, 'SUBSTACK');
    return result(source);
  }

  return {connectBlocks: connectBlocks, valueInputs: valueInputs};
}});
