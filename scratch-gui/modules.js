/*
 * The page's module registry. Every feature file (composite/, geometry/, primitive/, shared/)
 * registers one named module, and nothing else, with
 *
 *   scratchworldModule({name, requires: [names], create(ctx, ...required) {
 *     return {api: {bridgeFunction: (args) => ...}, helper: ...};
 *   }});
 *
 * The bridge (bridge.js, loaded after every module) creates the modules in dependency order,
 * gives each the bridge context `ctx` (the VM accessor, the failure type, the real clock, ...)
 * and what the modules it requires returned, and joins every module's `api` into its one call
 * table. The rest of what `create` returns is what other modules see. Files load as plain
 * scripts, so this registry is the only global they touch, and the bridge removes it.
 */
(function () {
  'use strict';

  const specs = [];
  window.__scratchworldModules = specs;
  window.scratchworldModule = (spec) => {
    if (!spec || typeof spec.name !== 'string' || typeof spec.create !== 'function') {
      throw new Error('a page module needs a name and a create function');
    }
    specs.push({name: spec.name, requires: spec.requires || [], create: spec.create});
  };
})();
