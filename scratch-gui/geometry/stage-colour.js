/*
 * Where the stage shows a colour: what the colour picker's eyedropper would pick at a page point.
 * The GUI's eyedropper takes the renderer's pixel at the stage point under the pointer
 * (`renderer.extractColor`, one pixel per stage unit); this renders the whole stage the same way
 * once and finds a page point inside an area of exactly that colour. Read-only (the renderer draws
 * into its own query buffer, not onto the stage).
 */
scratchworldModule({name: 'geometry/stage-colour', requires: ['rects'], create(ctx, rects) {
  'use strict';

  // Page pixels around the chosen point that must show the colour too (a pointer is a pixel off).
  const MARGIN = 2;

  function hex(value) {
    return value.toString(16).padStart(2, '0');
  }

  function stagePixel(args) {
    const wanted = String(args.colour || '').toLowerCase();
    if (!/^#[0-9a-f]{6}$/.test(wanted)) throw new ctx.BridgeFailure('bad_request', 'colour must be #rrggbb');
    const renderer = ctx.requireVm().renderer;
    const canvas = renderer.gl.canvas;
    const stage = rects.rectOf(canvas);
    const [nativeWidth, nativeHeight] = renderer.getNativeSize();
    const radius = Math.ceil(Math.max(nativeWidth, nativeHeight) / 2);
    const picked = renderer.extractColor(canvas.clientWidth / 2, canvas.clientHeight / 2, radius);
    // The colour the eyedropper takes at a point of the canvas (client pixels), as extractColor maps it.
    const colourAt = (x, y) => {
      const scratchX = Math.round(nativeWidth * ((x / canvas.clientWidth) - 0.5));
      const scratchY = Math.round(-nativeHeight * ((y / canvas.clientHeight) - 0.5));
      const px = scratchX + radius;
      const py = radius - scratchY;
      if (px < 0 || py < 0 || px >= picked.width || py >= picked.height) return null;
      const base = 4 * (py * picked.width + px);
      return `#${hex(picked.data[base])}${hex(picked.data[base + 1])}${hex(picked.data[base + 2])}`;
    };
    for (let y = MARGIN; y < canvas.clientHeight - MARGIN; y++) {
      for (let x = MARGIN; x < canvas.clientWidth - MARGIN; x++) {
        let solid = true;
        for (let dy = -MARGIN; dy <= MARGIN && solid; dy++) {
          for (let dx = -MARGIN; dx <= MARGIN && solid; dx++) solid = colourAt(x + dx, y + dy) === wanted;
        }
        if (solid) return {found: true, point: {x: stage.x + x, y: stage.y + y}, stage: stage};
      }
    }
    return {found: false, point: null, stage: stage};
  }

  return {api: {geometryStagePixel: (args) => stagePixel(args)}};
}});
