/*
 * A drag task's view, set semantically: the editing target by name, the palette category and how
 * far its flyout is scrolled, and the workspace's scale and scroll. Upstream set the same view
 * with pixel clicks; set this way it is the same on any layout. The target is selected first and
 * on its own (`dragSelectTarget`): the editor redraws the workspace asynchronously, so Python
 * waits for the page to settle before `dragSetView` places the rest (and `dragViewState` tells whether it
 * stayed there). `dragRendered` paces a real
 * drag: each pointer move is drawn before the next is made, as in a drag by hand.
 */
scratchworldModule({name: 'drag/view', requires: ['blockly'], create(ctx, blockly) {
  'use strict';

  const fail = (message) => new ctx.BridgeFailure('bad_request', message);

  function selectTarget(args) {
    const vm = ctx.requireVm();
    const sprite = args.sprite;
    let target;
    if (sprite === null || sprite === undefined) {
      target = vm.runtime.getTargetForStage();
    } else {
      if (typeof sprite !== 'string') throw fail('sprite must be a name or null (the Stage)');
      target = vm.runtime.targets.find((t) => t.isOriginal && !t.isStage && t.getName() === sprite);
    }
    if (!target) throw new ctx.BridgeFailure('not_found', `no sprite named ${JSON.stringify(sprite)}`);
    if (vm.editingTarget !== target) vm.setEditingTarget(target.id);
    return {editingTarget: target.getName()};
  }

  function number(args, name) {
    const value = args[name];
    if (typeof value !== 'number' || !Number.isFinite(value)) throw fail(`${name} must be a finite number`);
    return value;
  }

  // The flyout scrolled so that `category` starts at its top, then `offset` flyout pixels further
  // (what a mouse wheel's deltaY scrolls), without the scroll animation a click would start.
  function showCategory(category, offset) {
    const ws = blockly.workspace();
    const toolbox = ws.getToolbox();
    const item = toolbox.getToolboxItemById(category);
    if (!item) throw new ctx.BridgeFailure('not_found', `the palette has no category ${JSON.stringify(category)}`);
    const flyout = blockly.flyout();
    toolbox.setSelectedItem(item);
    const position = flyout.getCategoryScrollPosition(item.getName());
    if (position === null) throw new ctx.BridgeFailure('editor_not_ready', `the palette has not laid out ${category} yet`);
    const flyoutWs = flyout.getWorkspace();
    const metrics = flyoutWs.getMetrics();
    const top = Math.min(Math.ceil(position) * flyoutWs.scale + offset, metrics.scrollHeight - metrics.viewHeight);
    flyout.scrollTarget = undefined;
    flyoutWs.scrollbar.setY(Math.max(0, top));
    return -flyoutWs.scrollY;
  }

  // Scale, then the canvas translation that puts workspace (scrollX, scrollY) at the SVG's top-left
  // corner, with the workspace's own scroll state agreeing (as the GUI restores a target's view).
  function placeWorkspace(scale, scrollX, scrollY) {
    const ws = blockly.workspace();
    ws.setScale(scale);
    const metrics = ws.getMetrics();
    const tx = -scrollX * scale;
    const ty = -scrollY * scale;
    ws.scrollX = tx - metrics.absoluteLeft;
    ws.scrollY = ty - metrics.absoluteTop;
    ws.translate(tx, ty);
    return {tx: tx, ty: ty, scale: ws.scale};
  }

  function setView(args) {
    const scale = number(args, 'scale');
    if (!(scale > 0)) throw fail('scale must be positive');
    const placed = placeWorkspace(scale, number(args, 'scroll_x'), number(args, 'scroll_y'));
    let flyoutTop = null;
    if (args.category !== null && args.category !== undefined) {
      if (typeof args.category !== 'string') throw fail('category must be a category id or null');
      flyoutTop = showCategory(args.category, number(args, 'flyout_scroll'));
    }
    return Object.assign(placed, {flyoutTop: flyoutTop});
  }

  // Where the canvas is now: its translation on the workspace SVG and its scale. The editor can move the
  // canvas after `setView` (restoring a target's last scroll as it redraws the target's scripts; clamping
  // the scroll when the palette reflows): Python compares this with what `setView` placed, and places it
  // again when it moved.
  function viewState() {
    const ws = blockly.workspace();
    const m = ws.getCanvas().getCTM();
    return {tx: m.e, ty: m.f, scale: ws.scale};
  }

  // A view that shows `blocks` (ids; their whole scripts) in the visible workspace at `scale` (default:
  // the current zoom), centred when they fit, else from their top-left corner; and, for a palette source,
  // the flyout scroll (from the top of `category`) that shows its block near the top of the palette. For
  // generating tasks.
  function frame(args) {
    const ws = blockly.workspace();
    const ids = Array.isArray(args.blocks) ? args.blocks : [];
    let box = null;
    for (const id of ids) {
      const block = ws.getBlockById(id);
      if (!block) throw new ctx.BridgeFailure('not_found', `no block ${JSON.stringify(id)} on the workspace`);
      const r = block.getRootBlock().getBoundingRectangle();
      box = box ? {left: Math.min(box.left, r.left), top: Math.min(box.top, r.top), right: Math.max(box.right, r.right), bottom: Math.max(box.bottom, r.bottom)} : {left: r.left, top: r.top, right: r.right, bottom: r.bottom};
    }
    if (!box) throw fail('blocks must name at least one block');
    // At the given zoom (a used page may still be zoomed as its last view was), else at the current one.
    const scale = args.scale === undefined || args.scale === null ? ws.scale : number(args, 'scale');
    if (!(scale > 0)) throw fail('scale must be positive');
    const svg = ws.getParentSvg().getBoundingClientRect();
    const metrics = ws.getMetrics();
    const margin = 40;
    const view = {left: metrics.absoluteLeft + margin, top: metrics.absoluteTop + margin, width: metrics.viewWidth - 2 * margin - 60, height: metrics.viewHeight - 2 * margin - 60};
    const width = (box.right - box.left) * scale;
    const height = (box.bottom - box.top) * scale;
    const left = width < view.width ? view.left + (view.width - width) / 2 : view.left;
    const top = height < view.height ? view.top + (view.height - height) / 2 : view.top;
    const result = {scroll_x: box.left - left / scale, scroll_y: box.top - top / scale, scale: scale, fits: width <= view.width && height <= view.height, svg: {x: svg.left, y: svg.top}};
    if (typeof args.opcode === 'string' && typeof args.category === 'string') {
      const flyout = blockly.flyout();
      const flyoutWs = flyout.getWorkspace();
      const item = ws.getToolbox().getToolboxItemById(args.category);
      const position = item ? flyout.getCategoryScrollPosition(item.getName()) : null;
      const block = flyoutWs.getTopBlocks(false).find((b) => b.type === args.opcode &&
        (!args.variable_name || (b.getField('VARIABLE') && b.getField('VARIABLE').getText() === args.variable_name)));
      if (position === null || !block) throw new ctx.BridgeFailure('not_found', `the palette shows no ${args.opcode} under ${args.category}`);
      const below = (block.getRelativeToSurfaceXY().y - Math.ceil(position)) * flyoutWs.scale;
      result.flyout_scroll = Math.max(0, Math.round(below - 120));
    }
    return result;
  }

  // Resolves once Blockly has drawn what the last pointer move changed (a connection preview moves
  // the blocks after it, and with them the connections the next move is matched against).
  function rendered() {
    const management = blockly.scratchBlocks().renderManagement;
    return Promise.resolve(management && management.finishQueuedRenders ? management.finishQueuedRenders() : null)
      .then(() => ({rendered: true}));
  }

  return {
    api: {
      dragSelectTarget: (args) => selectTarget(args), dragSetView: (args) => setView(args), dragFrame: (args) => frame(args),
      dragRendered: () => rendered(), dragViewState: () => viewState(),
    },
  };
}});
