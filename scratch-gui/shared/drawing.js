/*
 * The stage drawn on demand: only when something looks at it. The VM asks for a frame on every step, but touching,
 * colour sensing and the pen do not read it: only a snapshot (`renderer.requestSnapshot`, answered inside `draw`)
 * and the canvas's own picture do. `evaluate` (an `on_demand` render) and `advanceClock` (an episode's advance)
 * draw so.
 */
scratchworldModule({name: 'drawing', create() {
  'use strict';

  // `draw` runs when a snapshot waits and just before the canvas is read. Returns the undo, which draws the last
  // frame unless told `{draw: false}`.
  function drawOnDemand(renderer) {
    const canvas = renderer.gl.canvas;
    const draw = renderer.draw;
    const hadOwnDraw = Object.prototype.hasOwnProperty.call(renderer, 'draw');
    let drawing = false;
    const drawNow = () => {
      if (drawing) return; // draw itself reads the canvas for a snapshot
      drawing = true;
      try { draw.call(renderer); } finally { drawing = false; }
    };
    renderer.draw = () => { if (renderer._snapshotCallbacks && renderer._snapshotCallbacks.length) drawNow(); };
    const readers = {};
    for (const name of ['toDataURL', 'toBlob']) {
      readers[name] = canvas[name];
      canvas[name] = function (...args) { drawNow(); return readers[name].apply(canvas, args); };
    }
    return ({draw: drawLast = true} = {}) => {
      if (hadOwnDraw) renderer.draw = draw; else delete renderer.draw;
      for (const name of Object.keys(readers)) delete canvas[name];
      if (!drawLast) return;
      try { draw.call(renderer); } catch (e) { /* the page shows the last frame drawn; the verdict stands */ }
    };
  }

  return {drawOnDemand};
}});
