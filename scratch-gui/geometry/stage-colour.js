/*
 * Where the stage shows a colour: what the colour picker's eyedropper would pick at a page point.
 * The GUI's eyedropper takes the renderer's pixel at the stage point under the pointer
 * (`renderer.extractColor`, one pixel per stage unit); this renders the whole stage the same way
 * once and finds a page point inside an area of exactly that colour. Read-only (the renderer draws
 * into its own query buffer, not onto the stage).
 */
scratchworldModule({name: 'geometry/stage-colour', requires: ['rects'], create(ctx, rects) {
  'use strict';

  // Page pixels around the chosen point that should show the colour too (a pointer may be a pixel off): the
  // widest margin any point of the stage offers, down to none (a colour drawn in single pixels only, as a
  // small stage shows thin shapes; the exact point is then clicked, and the oracle checks what was picked).
  const MARGINS = [2, 1, 0];

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
    for (const margin of MARGINS) {
      for (let y = margin; y < canvas.clientHeight - margin; y++) {
        for (let x = margin; x < canvas.clientWidth - margin; x++) {
          let solid = true;
          for (let dy = -margin; dy <= margin && solid; dy++) {
            for (let dx = -margin; dx <= margin && solid; dx++) solid = colourAt(x + dx, y + dy) === wanted;
          }
          if (solid) return {found: true, point: {x: stage.x + x, y: stage.y + y}, stage: stage};
        }
      }
    }
    return {found: false, point: null, stage: stage};
  }

  return {api: {geometryStagePixel: (args) => stagePixel(args)}};
}});
