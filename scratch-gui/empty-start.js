/*
 * An empty first project for an editor opened ahead of its use.
 *
 * As it starts, the GUI loads its built-in default project: the stage and the cat sprite, with the cat's
 * costumes drawn and its panels filled. An editor opened ahead (a pool's, whose address carries
 * `?start=empty`) never shows that project: every use loads the task's project first, which replaces it,
 * as a recycled page's next project replaces the last. For such a page the built-in default is a stage
 * with the default project's blank backdrop and nothing else. Measured on one browser's openings from the
 * third, alternating (docs/measuring.md): 1.50 CPU-s at the median against 1.61. An editor opened for
 * direct use keeps the default project.
 * The bridge takes this from `window.__scratchworldEmptyStart` (and deletes it) and hands it the GUI's
 * storage (`onStorageInit`, which the GUI calls before it fetches the default project); the bare page has
 * no GUI and does not load this script.
 */
(function () {
  'use strict';

  const DEFAULT_PROJECT_ID = '0'; // the GUI's id for its built-in default project
  const BLANK_BACKDROP = 'cd21514d0531fdffb22204e0ec5ed84a'; // the default project's backdrop, stored with it

  const EMPTY_PROJECT = {
    targets: [{
      isStage: true, name: 'Stage', variables: {}, lists: {}, broadcasts: {}, blocks: {}, comments: {},
      currentCostume: 0,
      costumes: [{
        name: 'backdrop1', assetId: BLANK_BACKDROP, md5ext: `${BLANK_BACKDROP}.svg`, dataFormat: 'svg',
        rotationCenterX: 240, rotationCenterY: 180,
      }],
      sounds: [], volume: 100, layerOrder: 0, tempo: 60, videoTransparency: 50, videoState: 'on',
      textToSpeechLanguage: null,
    }],
    monitors: [],
    extensions: [],
    meta: {semver: '3.0.0', vm: '0.2.0', agent: ''},
  };

  // Whether this page was opened ahead (its address asks for the empty start).
  const wanted = () => new URLSearchParams(window.location.search).get('start') === 'empty';

  // Store the empty project under the default's id, where the GUI's fetch finds it first (the GUI stores
  // its own default the same way, through the storage's built-in helper). True if it did.
  function replaceDefault(storage) {
    if (!wanted()) return false;
    const data = new TextEncoder().encode(JSON.stringify(EMPTY_PROJECT));
    storage.builtinHelper._store(storage.AssetType.Project, storage.DataFormat.JSON, data, DEFAULT_PROJECT_ID);
    return true;
  }

  window.__scratchworldEmptyStart = Object.freeze({replaceDefault});
})();
