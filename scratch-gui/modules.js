/*
 * The page's module registry. Every feature file (composite/, geometry/, primitive/, shared/)
 * registers one named module, and nothing else, with
 *
 *   scratchworldModule({name, requires: [names], create(ctx, ...required) {
 *     return {api: {bridgeFunction: (args) => ...}, helper: ...};
 *   }});
 *
 * The bridge (bridge.js, loaded after every module) has the registry create them (`createAll`):
 * in dependency order, each given the bridge context `ctx` (the VM accessor, the failure type,
 * the real clock, ...) and what the modules it requires returned; it then joins every module's
 * `api` into its one call table. The rest of what `create` returns is what other modules (and the bridge's
 * own functions: `evaluate` uses evaluation/script and drawing) see. Files load as plain
 * scripts, so this registry is the only global they touch, and the bridge removes it.
 */
(function () {
  'use strict';

  const specs = [];
  window.scratchworldModule = (spec) => {
    if (!spec || typeof spec.name !== 'string' || typeof spec.create !== 'function') {
      throw new Error('a page module needs a name and a create function');
    }
    specs.push({name: spec.name, requires: spec.requires || [], create: spec.create});
  };

  // Every registered module, created in dependency order: each gets the bridge context and what the
  // modules it requires returned; by name, what each returned. The bridge calls this once, after every
  // module file has loaded.
  function createAll(ctx) {
    const byName = new Map();
    for (const spec of specs) {
      if (byName.has(spec.name)) throw new Error(`page module ${spec.name} registered twice`);
      byName.set(spec.name, spec);
    }
    const created = new Map();
    const creating = new Set();
    function create(name, by) {
      if (created.has(name)) return created.get(name);
      const spec = byName.get(name);
      if (!spec) throw new Error(`page module ${name} (required by ${by}) is not loaded: is it in index.html?`);
      if (creating.has(name)) throw new Error(`page modules require each other in a cycle through ${name}`);
      creating.add(name);
      const instance = spec.create(ctx, ...spec.requires.map((required) => create(required, name))) || {};
      created.set(name, instance);
      return instance;
    }
    for (const name of byName.keys()) create(name, 'index.html');
    return created;
  }

  window.__scratchworldModules = {createAll: createAll};
})();
