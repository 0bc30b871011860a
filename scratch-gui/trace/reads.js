/*
 * What an evaluation script looks at (the grader audit's vacuity check, workers/kinds/audit): while the
 * script runs, which fields of the observable trace (trace/observe.js) it reads, and whether it starts
 * the program at all. Asked for with `evaluate`'s `observeReads: true`; Python takes the result with
 * `takeObservedReads`: {flags, threads, reads: [[target, field]], events: [name]}.
 *
 * - A read is a property or method of a target (x, y, direction, size, costume, visibility, effects,
 *   rotation style, its bubble, pen or sound bank, touching and bounds, which read its place), or a
 *   variable's value, whose caller is the script or its helper (their code carries their file names,
 *   `//# sourceURL` in bridge.js): the VM's own reads, also those a script's call makes it do
 *   (stopping clears effects), are not the script's. Targets are named as the trace names them, a
 *   clone by its sprite's name; a variable is `var:<id>` of its owner.
 * - Listening to the VM's SAY (bubbles), QUESTION (the ask prompt) or clone events reads those fields of
 *   any target (`*`).
 * - `flags` counts green flags, `threads` the scripts started from outside a VM step (the flag, keys,
 *   clicks, broadcasts a script sends): a script that starts nothing never ran the program.
 * Everything hooked is put back when the script is done.
 */
scratchworldModule({name: 'trace/reads', create(ctx) {
  'use strict';

  const PROPERTIES = {
    x: ['x'], y: ['y'], direction: ['direction'], size: ['size'], currentCostume: ['costume'],
    visible: ['visible'], effects: ['effects'], rotationStyle: ['rotation'],
  };
  const METHODS = {
    getBounds: ['x', 'y'], isTouchingObject: ['x', 'y'], isTouchingSprite: ['x', 'y'], isTouchingEdge: ['x', 'y'],
    isTouchingColor: ['x', 'y'], colorIsTouchingColor: ['x', 'y'], getLayerOrder: ['layers'],
  };
  const STATES = {'Scratch.looks': 'bubble', 'Scratch.pen': 'pen'};
  const EVENTS = {SAY: 'bubble', QUESTION: 'question', targetWasCreated: 'present', targetWasRemoved: 'present'};
  let last = null; // the last evaluation's reads, until Python takes them

  const keyOf = (target) => (target.isStage ? 'Stage' : target.sprite ? target.sprite.name : String(target.getName()));

  function observer(vm, args) {
    const runtime = vm.runtime;
    const files = [args.scriptName || 'evaluation.js', args.helperName].filter(Boolean).map((name) => `${encodeURI(name)}:`);
    const reads = new Set();
    const events = new Set();
    const undo = [];
    let flags = 0;
    let threads = 0;
    let stepping = 0;

    // Whether the caller of the hook that calls this is the script (frames: this, the hook, its caller).
    function fromScript() {
      const limit = Error.stackTraceLimit;
      Error.stackTraceLimit = 3;
      const stack = new Error().stack || '';
      Error.stackTraceLimit = limit;
      const caller = stack.split('\n')[3] || '';
      return files.some((file) => caller.includes(file));
    }
    const note = (target, fields) => {
      for (const field of fields) reads.add(`${keyOf(target)}\u0000${field}`);
    };

    // A data property read through an accessor (writes pass through); put back as data with its value.
    function watchProperty(object, name, onRead) {
      const own = Object.getOwnPropertyDescriptor(object, name);
      if (!own || !('value' in own) || !own.configurable) return;
      let value = own.value;
      Object.defineProperty(object, name, {
        configurable: true, enumerable: own.enumerable,
        get() {
          if (fromScript()) onRead();
          return value;
        },
        set(next) { value = next; },
      });
      undo.push(() => Object.defineProperty(object, name, {...own, value: value}));
    }

    // Replaces a method by a wrapper made of the original; removed afterwards (left passing calls through
    // when something wrapped it again since).
    function wrap(object, name, make) {
      const hadOwn = Object.prototype.hasOwnProperty.call(object, name);
      const original = object[name];
      if (typeof original !== 'function') return;
      let active = true;
      const hooked = make(original);
      const wrapper = function () {
        return (active ? hooked : original).apply(this, arguments);
      };
      object[name] = wrapper;
      undo.push(() => {
        active = false;
        if (object[name] !== wrapper) return;
        if (hadOwn) object[name] = original;
        else delete object[name];
      });
    }
    // A method whose calls by the script are noted (`onCall` with the call's arguments) before it runs.
    const watchMethod = (object, name, onCall) => wrap(object, name, (original) => function () {
      if (fromScriptOfWrapper()) onCall.apply(this, arguments);
      return original.apply(this, arguments);
    });
    // The same test one frame further up (the wrapper calls the hooked function, which calls this).
    function fromScriptOfWrapper() {
      const limit = Error.stackTraceLimit;
      Error.stackTraceLimit = 4;
      const stack = new Error().stack || '';
      Error.stackTraceLimit = limit;
      const caller = stack.split('\n')[4] || '';
      return files.some((file) => caller.includes(file));
    }

    function watchTarget(target) {
      for (const [name, fields] of Object.entries(PROPERTIES)) watchProperty(target, name, () => note(target, fields));
      for (const [name, fields] of Object.entries(METHODS)) watchMethod(target, name, () => note(target, fields));
      watchMethod(target, 'getCustomState', (name) => {
        if (STATES[name] === 'pen') reads.add('Stage\u0000pen');
        else if (STATES[name]) note(target, [STATES[name]]);
      });
      for (const variable of Object.values(target.variables || {})) {
        if (variable.type !== 'broadcast_msg') watchProperty(variable, 'value', () => note(target, [`var:${variable.id}`]));
      }
      if (target.sprite && !target.isStage && target.isOriginal) {
        watchProperty(target.sprite, 'soundBank', () => note(target, ['sounds']));
      }
    }

    return {
      start() {
        runtime.targets.forEach(watchTarget);
        const onCreated = (target) => watchTarget(target);
        runtime.on('targetWasCreated', onCreated);
        undo.push(() => runtime.removeListener('targetWasCreated', onCreated));
        wrap(runtime, '_step', (original) => function () {
          stepping += 1;
          try { return original.apply(this, arguments); } finally { stepping -= 1; }
        });
        wrap(runtime, 'greenFlag', (original) => function () {
          if (stepping === 0) flags += 1;
          return original.apply(this, arguments);
        });
        wrap(runtime, 'startHats', (original) => function () {
          const started = original.apply(this, arguments);
          if (stepping === 0 && Array.isArray(started)) threads += started.length;
          return started;
        });
        for (const name of ['on', 'addListener', 'once']) {
          watchMethod(runtime, name, (event) => {
            if (Object.prototype.hasOwnProperty.call(EVENTS, event)) events.add(String(event));
          });
        }
      },
      stop() {
        for (const step of undo.reverse()) step();
        const pairs = [...reads].map((read) => read.split('\u0000'));
        for (const event of events) pairs.push(['*', EVENTS[event]]);
        last = {flags, threads, reads: pairs, events: [...events].sort()};
      },
    };
  }

  ctx.onEvaluation((vm, args) => {
    last = null;
    return args.observeReads === true ? observer(vm, args) : null;
  });
  ctx.onProjectLoaded(() => { last = null; });

  return {
    api: {
      takeObservedReads: () => {
        const taken = last;
        last = null;
        return taken;
      },
    },
  };
}});
