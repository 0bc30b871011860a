/*
 * The editor's palette, held empty until its first use.
 *
 * The GUI draws its palette (every block of every category, rendered as SVG) when the code area mounts,
 * from a stage's toolbox kept in its store, then again for the default project's sprite once that project
 * has loaded, and again when its locale is set. An editor opened ahead draws none of them: `hold` seeds
 * the store with the categories empty and keeps them so (each toolbox the GUI sends on is stored with its
 * categories emptied, the real one kept aside), so the mount draws labels only. The hold ends either
 * - at the page's first project load (`stopHolding`, from the bridge's `loadProject`): that load sends the
 *   project's own toolbox, which is drawn once, as a used page draws each project's; the default
 *   project's palette, which every use replaces, is never drawn; or
 * - when somebody wants the default project's palette (`release`, the bridge's `drawPalette`): the toolbox
 *   kept aside is sent on and drawn.
 * tests/workers/editor/test_browser_session.py counts the drawings. Measured on one browser's openings
 * from the third on (docs/measuring.md): 1.93-2.09 CPU-s per opening with three drawings, 1.76-1.83 with
 * the sprite's one; on a slower evening, 2.13-2.22 with the sprite's one and 1.69-1.77 with none.
 * The bridge takes this from `window.__scratchworldFirstPalette` (and deletes it); the bare page has no
 * palette and does not load this script.
 */
(function () {
  'use strict';

  const UPDATE_TOOLBOX = 'scratch-gui/toolbox/UPDATE_TOOLBOX';

  let held = null; // while held: {store, dispatch, kept: the latest real toolbox, sent: toolboxes sent on}

  // The toolbox with its categories' blocks removed, or null if it does not parse.
  function emptied(xml) {
    const doc = new DOMParser().parseFromString(xml, 'text/xml');
    if (doc.querySelector('parsererror')) return null;
    for (const category of doc.querySelectorAll('category')) category.replaceChildren();
    return new XMLSerializer().serializeToString(doc);
  }

  // Before the GUI first renders (its components take `store.dispatch` when they mount).
  function hold(store) {
    const xml = store.getState().scratchGui.toolbox.toolboxXML;
    const empty = emptied(xml);
    if (empty === null) return; // left as it is: drawn as the GUI draws it
    const dispatch = store.dispatch;
    held = {store: store, dispatch: dispatch, kept: xml, sent: 0};
    store.dispatch = (action) => {
      if (held && action && action.type === UPDATE_TOOLBOX) {
        const heldEmpty = emptied(action.toolboxXML);
        if (heldEmpty !== null) {
          held.kept = action.toolboxXML;
          held.sent += 1;
          return dispatch(Object.assign({}, action, {toolboxXML: heldEmpty}));
        }
      }
      return dispatch(action);
    };
    dispatch({type: UPDATE_TOOLBOX, toolboxXML: empty});
  }

  // The GUI has sent its sprite's toolbox since the hold began: the editor's start is over as far as the
  // palette goes (what it would have drawn is kept aside).
  const waiting = () => held !== null && held.sent > 0;

  // The next toolbox the GUI sends is drawn as it is (a project load sends its own).
  function stopHolding() {
    held = null;
  }

  // Draw the toolbox kept aside, unless another has reached the store meanwhile. True if one was sent on.
  function release() {
    if (!held) return false;
    const {store, dispatch, kept} = held;
    held = null;
    if (store.getState().scratchGui.toolbox.toolboxXML !== emptied(kept)) return false;
    dispatch({type: UPDATE_TOOLBOX, toolboxXML: kept});
    return true;
  }

  window.__scratchworldFirstPalette = Object.freeze({hold, waiting, isHeld: () => held !== null, stopHolding, release});
})();
