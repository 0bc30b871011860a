/*
 * Primitive mode, page side: whether the latest press started an HTML5 drag-and-drop that is still
 * under way, so that a drag's later moves may skip Playwright's per-move drag interception
 * (workers/primitive/_pressed_moves.py). Chromium decides at a press's first move past its drag
 * threshold whether the press starts an HTML5 drag; Playwright carries such a drag on with drag
 * events, and that part stays Playwright's. Read-only: the listeners only take note.
 */
scratchworldModule({name: 'primitive/html5-drag', create() {
  'use strict';

  let started = null; // the latest press's dragstart, until its dragend
  const capture = {capture: true};
  window.addEventListener('pointerdown', () => { started = null; }, capture);
  window.addEventListener('dragstart', (event) => { started = event; }, capture);
  window.addEventListener('dragend', () => { started = null; }, capture);

  // Read after the move's handlers have all run, so a dragstart a handler cancelled counts as none.
  function primitiveDragging() {
    return {dragging: started !== null && !started.defaultPrevented};
  }

  return {api: {primitiveDragging: primitiveDragging}};
}});
