/*
 * The editor's Blockly as every module reaches it: the visible workspace, its palette (flyout),
 * and whether the workspace shows exactly what the VM holds for the editing target.
 */
scratchworldModule({name: 'blockly', create(ctx) {
  'use strict';

  const component = () => ctx.blocksComponent();
  const scratchBlocks = () => component().ScratchBlocks;
  const workspace = () => component().workspace;

  function flyout() {
    const theFlyout = workspace().getFlyout();
    if (!theFlyout) throw new ctx.BridgeFailure('editor_not_ready', 'the palette (flyout) is not rendered');
    return theFlyout;
  }

  // {SB, ws, flyout, flyoutWs}, or null before Blockly has drawn the workspace (for readers
  // that must not fail on a page still opening).
  function drawn() {
    let found;
    try {
      found = component();
    } catch (e) {
      return null;
    }
    const ws = found.workspace;
    const theFlyout = ws.getFlyout ? ws.getFlyout() : null;
    return {SB: found.ScratchBlocks, ws: ws, flyout: theFlyout, flyoutWs: theFlyout ? theFlyout.getWorkspace() : null};
  }

  // The editing target's top-level scripts, as the VM holds them and as the workspace draws them.
  function topBlocks() {
    const target = ctx.requireVm().editingTarget;
    if (!target) return {vm: [], workspace: []};
    const vmTops = target.blocks.getScripts().map((id) => target.blocks.getBlock(id)).filter((b) => b && !b.shadow)
      .map((b) => ({id: b.id, opcode: b.opcode}));
    const wsTops = workspace().getTopBlocks(false).map((b) => ({id: b.id, opcode: b.type}));
    return {vm: vmTops, workspace: wsTops};
  }

  function dragging() {
    const ws = workspace();
    return typeof ws.isDragging === 'function' && ws.isDragging();
  }

  // True when the workspace shows exactly the editing target's scripts and nothing is being dragged.
  function inSync() {
    if (dragging()) return false;
    const tops = topBlocks();
    const a = tops.vm.map((b) => b.id).sort().join('\n');
    const b = tops.workspace.map((b) => b.id).sort().join('\n');
    return a === b;
  }

  // Runs `simulate()` with the workspace as a real drag leaves it: "a move in progress", and not
  // resizing. After every render Blockly bumps a script whose connections come near another's away
  // from it, by a random offset (snap radius + 0..9 units), unless a drag is in progress; and a
  // workspace that resizes to a block added or moved scrolls by a fraction of a pixel. A simulated
  // drag without this would see scripts and a view that a real drag never moves.
  function asIfDragging(simulate) {
    const ws = workspace();
    const moving = ws.keyboardMoveInProgress;
    const resizes = ws.resizesEnabled;
    ws.setKeyboardMoveInProgress(true);
    ws.setResizesEnabled(false);
    try {
      return simulate();
    } finally {
      ws.setResizesEnabled(resizes);
      ws.setKeyboardMoveInProgress(moving);
    }
  }

  return {
    scratchBlocks: scratchBlocks, workspace: workspace, flyout: flyout, drawn: drawn, topBlocks: topBlocks,
    dragging: dragging, inSync: inSync, asIfDragging: asIfDragging,
  };
}});
