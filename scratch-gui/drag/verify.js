/*
 * Whether a drag made the expected connection, read from the VM's block structure (what the
 * project will save), by the rule of each connection kind:
 *
 * - next: the source's parent is the reference and the reference's next is the source;
 * - parent: the reference hangs from the moving stack's tail (its parent, and the tail's next), and
 *   the tail still hangs below the source: the whole stack moved, not a part of it pulled off (which
 *   puts the same tail above the reference when dragged by the same offset);
 * - substack_1 / substack_2: the reference's SUBSTACK / SUBSTACK2 holds the source;
 * - input: the reference's named input holds the source (and, if named, the variable it reports).
 *
 * A palette source has no id before the drop: it is the new non-shadow block of its opcode that
 * `dragBlockIds` did not list before the drag. Read-only.
 */
scratchworldModule({name: 'drag/verify', requires: [], create(ctx) {
  'use strict';

  const fail = (message) => new ctx.BridgeFailure('bad_request', message);

  function blocksOfTarget() {
    const target = ctx.requireVm().editingTarget;
    if (!target) throw new ctx.BridgeFailure('editor_not_ready', 'no target is being edited');
    return target.blocks;
  }

  function blockIds() {
    return {ids: Object.keys(blocksOfTarget()._blocks)};
  }

  function describe(blocks, block) {
    if (!block) return 'the dragged block is gone (deleted)';
    if (!block.parent) return `the dragged ${block.opcode} is a top-level script`;
    const parent = blocks.getBlock(block.parent);
    if (!parent) return `the dragged ${block.opcode} hangs from a missing block`;
    if (parent.next === block.id) return `the dragged ${block.opcode} hangs below ${parent.opcode} ${parent.id}`;
    const input = Object.keys(parent.inputs).find((name) => parent.inputs[name].block === block.id);
    return `the dragged ${block.opcode} is in input ${input} of ${parent.opcode} ${parent.id}`;
  }

  function dragged(blocks, source, before) {
    if (source.kind === 'canvas') return blocks.getBlock(source.block_id) || null;
    if (!Array.isArray(before)) throw fail('a palette source needs before: the block ids before the drag');
    const known = new Set(before);
    const fresh = Object.values(blocks._blocks).filter((b) => !known.has(b.id) && !b.shadow && b.opcode === source.opcode);
    // The dropped block itself, not a block it carries: the one whose parent is not new too.
    return fresh.find((b) => !b.parent || known.has(b.parent)) || fresh[0] || null;
  }

  // Whether `last` is `top` or hangs below it, next after next.
  function stackReaches(blocks, top, last) {
    for (let block = top; block; block = block.next ? blocks.getBlock(block.next) : null) {
      if (block === last) return true;
    }
    return false;
  }

  function connected(blocks, block, source, reference, connection) {
    const kind = connection.kind;
    if (kind === 'next') return block.parent === reference.id && reference.next === block.id;
    if (kind === 'parent') {
      // The moving stack's last block, as it was before the drop (a palette block is its own).
      const tail = source.kind === 'canvas' ? blocks.getBlock(source.tail_block_id) : block;
      return !!tail && reference.parent === tail.id && tail.next === reference.id && stackReaches(blocks, block, tail);
    }
    const name = kind === 'substack_1' ? 'SUBSTACK' : kind === 'substack_2' ? 'SUBSTACK2' : connection.input_name;
    const input = reference.inputs[name];
    if (!input || input.block !== block.id) return false;
    if (kind === 'input' && connection.variable_name) {
      return block.opcode === 'data_variable' && !!block.fields.VARIABLE && block.fields.VARIABLE.value === connection.variable_name;
    }
    return true;
  }

  function verify(args) {
    const blocks = blocksOfTarget();
    const connection = args.connection;
    if (!connection || typeof connection.kind !== 'string') throw fail('connection must be {kind, ...}');
    const reference = blocks.getBlock(args.reference);
    if (!reference) return {connected: false, observed: 'the reference block is gone'};
    const source = args.source || {};
    const block = dragged(blocks, source, args.before);
    const made = !!block && connected(blocks, block, source, reference, connection);
    return {connected: made, observed: describe(blocks, block), block: block ? block.id : null};
  }

  return {api: {dragBlockIds: () => blockIds(), dragVerify: (args) => verify(args)}};
}});
