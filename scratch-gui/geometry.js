/* geometry.js: placeholder, being written. */
(function () {
  'use strict';
  function factory(ctx) {
    return {};
  }
  const modules = window.__scratchworldModules = window.__scratchworldModules || [];
  modules.push(factory);
})();
