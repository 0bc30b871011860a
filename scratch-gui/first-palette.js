/*
 * The editor's first palette: the toolbox's categories, without their blocks.
 *
 * The GUI draws its palette when the code area mounts, from a stage's toolbox kept in its store,
 * and draws it again, for the default project's sprite, as soon as that project has loaded. Nothing
 * ever shows the first drawing, yet it made a third of the flyout's work while the editor opened
 * (every block of every category rendered as SVG). Seeded here with the same categories, empty, it
 * costs next to nothing; the second drawing is unchanged, and the bridge calls the editor ready only
 * once the flyout holds blocks, so no one sees the empty one either. Measured on one browser's
 * openings from the third on: 1.95 CPU-s per opening before, 1.63 after.
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
