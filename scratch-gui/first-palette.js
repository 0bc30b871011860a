/*
 * The editor's first palette: the toolbox's categories, without their blocks.
 *
 * The GUI draws its palette when the code area mounts, from a stage's toolbox kept in its store, then
 * again for the default project's sprite once that project has loaded, and again when its locale is
 * set: every block of every category rendered as SVG each time, and no one sees the first drawings.
 * Seeded here with the same categories, empty, the mount draws labels only and the sprite's palette is
 * drawn once (tests/workers/editor/test_browser_session.py counts the drawings); the bridge calls the
 * editor ready only once the flyout holds blocks, so no one sees the empty one either. Measured on one
 * browser's openings from the third on (docs/measuring.md): 1.93-2.09 CPU-s per opening before,
 * 1.76-1.83 after.
 * The bridge takes `seed` from `window.__scratchworldFirstPalette` (and deletes it); the bare page has
 * no palette and does not load this script.
 */
(function () {
  'use strict';

  const UPDATE_TOOLBOX = 'scratch-gui/toolbox/UPDATE_TOOLBOX';

  // Empties the store's toolbox before the GUI first renders; left as it is if it does not parse.
  function seed(store) {
    const xml = store.getState().scratchGui.toolbox.toolboxXML;
    const doc = new DOMParser().parseFromString(xml, 'text/xml');
    if (doc.querySelector('parsererror')) return;
    for (const category of doc.querySelectorAll('category')) category.replaceChildren();
    store.dispatch({type: UPDATE_TOOLBOX, toolboxXML: new XMLSerializer().serializeToString(doc)});
  }

  window.__scratchworldFirstPalette = {seed: seed};
})();
