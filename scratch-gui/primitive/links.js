/*
 * Primitive mode, page side: which block hangs from which in the visible workspace, so a drag's
 * record can say whether it snapped. Read from Blockly (it connects on mouse-up, synchronously),
 * not from the VM, which hears of the move only when Blockly's event queue fires. Read-only.
 */
scratchworldModule({name: 'primitive/links', requires: ['blockly'], create(ctx, blockly) {
  'use strict';

  // [[block id, parent id or null, opcode], ...] of the workspace's non-shadow blocks.
  function primitiveLinks() {
    const found = blockly.drawn();
    if (!found) return {links: []};
    const links = found.ws.getAllBlocks(false).filter((block) => !block.isShadow()).map((block) => {
      const parent = block.getParent();
      return [block.id, parent ? parent.id : null, block.type];
    });
    return {links: links};
  }

  return {api: {primitiveLinks: primitiveLinks}};
}});
