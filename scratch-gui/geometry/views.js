/*
 * Where things are drawn, in page pixels: the visible workspace and the part of it where blocks
 * may be grabbed and dropped, what is drawn over it, its zoom-out button, the palette, the category
 * buttons and the sprite tiles (`geometryLayout`). Read-only, like every geometry module: the primitive oracle
 * plans real gestures from these views, and nothing here changes the page.
 */
scratchworldModule({name: 'geometry/views', requires: ['rects', 'blockly'], create(ctx, rects, blockly) {
  'use strict';

  // Inset of the usable workspace from its visible edges (scrollbars, zoom buttons live there).
  const EDGE = 12;
  const SCROLLBAR = 14;

  // Workspace coordinates of `ws` to page pixels, through the canvas's current transform.
  function toPage(ws, x, y) {
    const m = ws.getCanvas().getScreenCTM();
    return {x: m.a * x + m.c * y + m.e, y: m.b * x + m.d * y + m.f};
  }

  // The part of the main workspace that is visible on the page (right of the palette).
  function workspaceView() {
    const ws = blockly.workspace();
    const svg = ws.getParentSvg().getBoundingClientRect();
    const metrics = ws.getMetrics();
    const view = {x: svg.left + metrics.absoluteLeft, y: svg.top + metrics.absoluteTop, width: metrics.viewWidth, height: metrics.viewHeight};
    return rects.clip(view, rects.viewport());
  }

  // Where blocks may be dropped and grabbed: the visible workspace without its edges and scrollbars.
  function safeArea() {
    const view = workspaceView();
    return {x: view.x + EDGE, y: view.y + EDGE, width: view.width - 2 * EDGE - SCROLLBAR, height: view.height - 2 * EDGE - SCROLLBAR};
  }

  // Things drawn over the workspace that a dropped block must not land under, and that a wheel turn
  // over the workspace must miss: the zoom buttons, the watermark, and workspace comments (a wheel
  // turn over one scrolls its text, not the workspace).
  function overlays() {
    const found = [];
    for (const element of document.querySelectorAll('.blocklyZoom, [class*="watermark"], .blocklyWorkspace > .blocklyBlockCanvas > .blocklyComment')) {
      const r = rects.rectOf(element);
      if (r.width > 0 && r.height > 0) found.push(r);
    }
    return found;
  }

  function flyoutView() {
    const element = document.querySelector('.blocklyFlyout');
    if (!element) throw new ctx.BridgeFailure('editor_not_ready', 'the palette (flyout) is not rendered');
    return rects.clip(rects.rectOf(element), rects.viewport());
  }

  /* ---------- the page around the workspace ---------- */

  function categories() {
    return [...document.querySelectorAll('.blocklyToolboxCategory')].map((element) => ({
      name: element.textContent.trim(),
      rect: rects.rectOf(element),
      selected: element.classList.contains('blocklyToolboxSelected')
    }));
  }

  function targetTiles() {
    const sprites = [...document.querySelectorAll('[class*="sprite-selector_sprite-wrapper"]')].map((element) => {
      const label = element.querySelector('[class*="sprite-selector-item_sprite-name"]');
      return {name: (label || element).textContent.trim(), rect: rects.rectOf(element)};
    });
    const stageElement = document.querySelector('[class*="stage-selector_stage-selector"]');
    return {sprites: sprites, stage: stageElement ? rects.rectOf(stageElement) : null};
  }

  // The workspace's zoom-out button (a click zooms out around the view's centre), null when not drawn.
  function zoomOutButton(ws) {
    const element = ws.getParentSvg().querySelector('.blocklyZoomOut');
    const r = element ? rects.rectOf(element) : null;
    return r && r.width > 0 && r.height > 0 ? r : null;
  }

  function layout() {
    const ws = blockly.workspace();
    const vm = ctx.requireVm();
    return {
      workspace: workspaceView(),
      safeArea: safeArea(),
      overlays: overlays(),
      flyout: flyoutView(),
      scale: ws.scale,
      minScale: ws.options.zoomOptions ? ws.options.zoomOptions.minScale : ws.scale,
      zoomOut: zoomOutButton(ws),
      snapRadius: blockly.scratchBlocks().config.snapRadius,
      connectingSnapRadius: blockly.scratchBlocks().config.connectingSnapRadius,
      categories: categories(),
      targets: targetTiles(),
      editingTarget: vm.editingTarget ? vm.editingTarget.getName() : null,
      viewport: rects.viewport()
    };
  }

  return {
    toPage: toPage, workspaceView: workspaceView, safeArea: safeArea, overlays: overlays, flyoutView: flyoutView,
    api: {geometryLayout: () => layout()},
  };
}});
